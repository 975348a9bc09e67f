// The C header for drivers and the C++ header agree on every value a driver
// uses: offsets, reset values, access masks and field positions of every
// register named below, and the arrays' counts and strides.
#include <gtest/gtest.h>

#include "ceilnav/ceilnav_regs.h"
#include "ceilnav/regs.hpp"

namespace ceilnav::regs {
namespace {

#define EXPECT_REGISTER(c_name, ns)                               \
  do {                                                            \
    EXPECT_EQ(CEILNAV_##c_name##_OFFSET, ns::kOffset) << #c_name; \
    EXPECT_EQ(CEILNAV_##c_name##_RESVAL, ns::kReset) << #c_name;  \
    const Register* r = find(ns::kOffset);                        \
    ASSERT_NE(r, nullptr) << #c_name;                             \
    EXPECT_EQ(r->reset, ns::kReset) << #c_name;                   \
  } while (false)

#define EXPECT_FIELD(c_name, field)                               \
  do {                                                            \
    EXPECT_EQ(CEILNAV_##c_name##_LSB, field.lsb) << #c_name;      \
    EXPECT_EQ(CEILNAV_##c_name##_WIDTH, field.width) << #c_name;  \
    EXPECT_EQ(CEILNAV_##c_name##_MASK, field.mask()) << #c_name;  \
    EXPECT_EQ(CEILNAV_##c_name##_RESVAL, field.reset) << #c_name; \
  } while (false)

TEST(CHeader, RegistersAgreeWithTheCppHeader) {
  EXPECT_EQ(CEILNAV_ADDR_WIDTH, kAddrWidth);
  EXPECT_EQ(CEILNAV_PARAM_RUNFIFODEPTH, kRunFifoDepth);
  EXPECT_EQ(CEILNAV_PARAM_EDGEFIFODEPTH, kEdgeFifoDepth);
  EXPECT_EQ(CEILNAV_RESP_SLVERR, kRespSlvErr);
  EXPECT_REGISTER(ID, id);
  EXPECT_REGISTER(CONTROL, control);
  EXPECT_REGISTER(STATUS, status);
  EXPECT_REGISTER(INTR_STATE, intr_state);
  EXPECT_REGISTER(ERROR_CAUSE, error_cause);
  EXPECT_REGISTER(LUT_DATA, lut_data);
  EXPECT_REGISTER(HIST_DATA, hist_data);
  EXPECT_REGISTER(RUN_WORD3, run_word3);
  EXPECT_REGISTER(CLASS_WIN_X, class_win_x);
  EXPECT_EQ(CEILNAV_INTR_STATE_W1C_MASK, find(intr_state::kOffset)->w1c_mask);
  EXPECT_EQ(CEILNAV_CONTROL_RW_MASK, find(control::kOffset)->rw_mask);
  EXPECT_EQ(CEILNAV_CONTROL_WO_MASK, find(control::kOffset)->wo_mask);
  EXPECT_FIELD(CONTROL_SOFT_RESET, control::kSoftReset);
  EXPECT_FIELD(LUT_DATA_CLASS, lut_data::kClass);
  EXPECT_FIELD(CLASS_WIN_X_X1, class_win_x::kX1);
  EXPECT_FIELD(RUN_WORD0_ROW, run_word0::kRow);
  EXPECT_FIELD(HIST_DATA_COUNT, hist_data::kCount);
  EXPECT_REGISTER(EDGE_CONTROL, edge_control);
  EXPECT_REGISTER(EDGE_FIFO_DEPTH, edge_fifo_depth);
  EXPECT_FIELD(EDGE_CONTROL_MODE, edge_control::kMode);
  EXPECT_FIELD(EDGE_CONTROL_THRESHOLD, edge_control::kThreshold);
}

TEST(CHeader, ArraysAgreeWithTheCppHeader) {
  EXPECT_EQ(CEILNAV_CLASS_MOM_LO_COUNT, class_mom_lo::kCount);
  EXPECT_EQ(CEILNAV_CLASS_MOM_LO_STRIDE, class_mom_lo::kStride);
  for (uint32_t i = 0; i < class_mom_lo::kCount; ++i) {
    EXPECT_EQ(CEILNAV_CLASS_MOM_LO_OFFSET_I(i), class_mom_lo::kArray.at(i));
    EXPECT_EQ(CEILNAV_CLASS_MOM_HI_OFFSET_I(i), class_mom_hi::kArray.at(i));
  }
  for (uint32_t i = 0; i < mom_grey_lo::kCount; ++i) {
    EXPECT_EQ(CEILNAV_MOM_GREY_LO_OFFSET_I(i), mom_grey_lo::kArray.at(i));
    EXPECT_EQ(CEILNAV_MOM_MASK_HI_OFFSET_I(i), mom_mask_hi::kArray.at(i));
  }
}

}  // namespace
}  // namespace ceilnav::regs
