/* The generated C header for drivers, compiled as strict C99: its values
   against facts of the device that do not depend on the generator (the ID
   word, the addresses a driver hard-codes nowhere else, the interrupt
   registers' matching bits, the moment arrays). Exit 0 when all hold. */
#include <stdio.h>

#include "ceilnav/ceilnav_regs.h"

static int failures = 0;

static void check(int ok, const char* what) {
  if (!ok) {
    printf("FAIL: %s\n", what);
    ++failures;
  }
}

int main(void) {
  check(CEILNAV_ID_OFFSET == 0x000u, "ID at 0x000");
  check(CEILNAV_ID_RESVAL == 0x4345494Cu, "ID reads \"CEIL\"");
  check(CEILNAV_ADDR_WIDTH == 10u, "10-bit register window");
  check(CEILNAV_INTR_STATE_W1C_MASK == CEILNAV_INTR_ENABLE_RW_MASK,
        "INTR_STATE and INTR_ENABLE have the same bits");
  check(CEILNAV_INTR_TEST_WO_MASK == CEILNAV_INTR_ENABLE_RW_MASK,
        "INTR_TEST and INTR_ENABLE have the same bits");
  check(CEILNAV_INTR_STATE_FRAME_DONE_MASK == (1u << CEILNAV_INTR_STATE_FRAME_DONE_LSB),
        "FRAME_DONE mask and LSB agree");
  check(CEILNAV_MOM_GREY_LO_COUNT == 6u, "six moments m00..m02");
  check(CEILNAV_MOM_GREY_HI_OFFSET_I(5) == CEILNAV_MOM_GREY_LO_OFFSET_I(5) + 4u,
        "a moment's high word follows its low word");
  check(CEILNAV_LUT_DATA_CLASS_MASK == (3u << 9), "LUT class bits 10:9");
  check(CEILNAV_WIDTH_VALUE_RESVAL == 640u && CEILNAV_HEIGHT_VALUE_RESVAL == 480u,
        "640x480 after reset");
  check(CEILNAV_RUN_FIFO_DEPTH_VALUE_RESVAL == CEILNAV_PARAM_RUNFIFODEPTH,
        "RUN_FIFO_DEPTH reads the parameter");
  check(CEILNAV_EDGE_FIFO_DEPTH_VALUE_RESVAL == CEILNAV_PARAM_EDGEFIFODEPTH,
        "EDGE_FIFO_DEPTH reads the parameter");
  check(CEILNAV_EDGE_CONTROL_THRESHOLD_MASK == (0xFFFu << 16), "edge threshold bits 27:16");
  if (failures == 0) printf("ceilnav_regs.h: all checks hold\n");
  return failures == 0 ? 0 : 1;
}
