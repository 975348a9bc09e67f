// The CSV writer: RFC 4180 quoting and the fixed number formats.
#include "common/csv.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <sstream>

using ceilnav::CsvWriter;

TEST(CsvWriter, PlainFieldsAreNotQuoted) {
  EXPECT_EQ(CsvWriter::quote("frame_0001.png"), "frame_0001.png");
  EXPECT_EQ(CsvWriter::quote(""), "");
  EXPECT_EQ(CsvWriter::quote("a b;c"), "a b;c");
}

TEST(CsvWriter, SpecialCharactersAreQuotedAndQuotesDoubled) {
  EXPECT_EQ(CsvWriter::quote("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvWriter::quote("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvWriter::quote("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(CsvWriter::quote("cr\r"), "\"cr\r\"");
  EXPECT_EQ(CsvWriter::quote("\""), "\"\"\"\"");
}

TEST(CsvWriter, RowsSeparateFieldsAndEndInNewline) {
  std::ostringstream s;
  CsvWriter w(s);
  w.row({"name", "value"});
  w.text("x,y").integer(-3).end_row();
  w.empty().integer(true).integer(false).integer(std::uint64_t{18446744073709551615u}).end_row();
  EXPECT_EQ(s.str(), "name,value\n\"x,y\",-3\n,1,0,18446744073709551615\n");
}

TEST(CsvWriter, FixedMatchesPrintf) {
  std::ostringstream s;
  CsvWriter w(s);
  w.fixed(1.0 / 3.0, 4).fixed(2.5, 0).fixed(-0.00004, 4).fixed(1234.5678, 2).fixed(0.125, 6);
  w.end_row();
  EXPECT_EQ(s.str(), "0.3333,2,-0.0000,1234.57,0.125000\n");
}

TEST(CsvWriter, GeneralMatchesPrintf) {
  std::ostringstream s;
  CsvWriter w(s);
  w.general(0.1, 6).general(1e-7, 6).general(123456789.0, 6).general(2.0, 10);
  w.general(-0.0001234567891, 10).end_row();
  EXPECT_EQ(s.str(), "0.1,1e-07,1.23457e+08,2,-0.0001234567891\n");
}

TEST(CsvWriter, NonFiniteNumbersAreEmptyFields) {
  std::ostringstream s;
  CsvWriter w(s);
  w.fixed(std::numeric_limits<double>::quiet_NaN(), 3)
      .general(std::numeric_limits<double>::infinity(), 6)
      .fixed(-std::numeric_limits<double>::infinity(), 1)
      .integer(7)
      .end_row();
  EXPECT_EQ(s.str(), ",,,7\n");
}
