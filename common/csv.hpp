// The one CSV writer of the project: every table that apps, bench or golden
// writes goes through it, so quoting and number formats are the same everywhere.
//
// Fields follow RFC 4180: a field holding a comma, a double quote, CR or LF is
// enclosed in double quotes, and a double quote inside it is doubled. Rows end
// in "\n" (RFC 4180 names CRLF; every reader used here takes LF, and the files
// stay diffable). Numbers are formatted through fmt with an explicit format per
// column: fixed(v, digits) is printf's "%.<digits>f", general(v, significant)
// is printf's "%.<significant>g". A number that is not finite (NaN, inf) is an
// empty field: a missing value, never the text "nan".
#pragma once

#include <cmath>
#include <concepts>
#include <initializer_list>
#include <ostream>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace ceilnav {

class CsvWriter {
 public:
  explicit CsvWriter(std::ostream& out) : out_(out) {}

  // A whole row of text fields (typically the header).
  CsvWriter& row(std::initializer_list<std::string_view> fields) {
    for (std::string_view f : fields) text(f);
    return end_row();
  }

  // A text field, quoted when RFC 4180 requires it.
  CsvWriter& text(std::string_view s) {
    separate();
    out_ << quote(s);
    return *this;
  }

  // An integer field (bool writes 0 or 1).
  template <typename T>
  requires std::integral<T> CsvWriter& integer(T v) {
    separate();
    if constexpr (std::same_as<T, bool>) {
      out_ << (v ? '1' : '0');
    } else {
      out_ << fmt::format("{}", v);
    }
    return *this;
  }

  // A number with `digits` digits after the point ("%.<digits>f").
  CsvWriter& fixed(double v, int digits) {
    separate();
    if (std::isfinite(v)) out_ << fmt::format("{:.{}f}", v, digits);
    return *this;
  }

  // A number with `significant` significant digits ("%.<significant>g").
  CsvWriter& general(double v, int significant) {
    separate();
    if (std::isfinite(v)) out_ << fmt::format("{:.{}g}", v, significant);
    return *this;
  }

  // A field with no value.
  CsvWriter& empty() {
    separate();
    return *this;
  }

  CsvWriter& end_row() {
    out_ << '\n';
    first_ = true;
    return *this;
  }

  // `s` as one RFC 4180 field.
  static std::string quote(std::string_view s) {
    if (s.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(s);
    std::string q = "\"";
    for (char c : s) {
      if (c == '"') q += '"';
      q += c;
    }
    return q + '"';
  }

 private:
  void separate() {
    if (!first_) out_ << ',';
    first_ = false;
  }

  std::ostream& out_;
  bool first_ = true;
};

}  // namespace ceilnav
