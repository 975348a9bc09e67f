// Outcome of every host computation: a status, never a NaN.
#pragma once

#include <string_view>

namespace ceilnav::host {

enum class Status {
  ok,
  no_tape,         // no runs / nothing bright in the frame
  too_few_points,  // not enough run centres for a robust line fit
  degenerate,      // geometry cannot be solved (line parallel to horizon, zero motion, ...)
  bad_config,      // configuration out of range
  frame_invalid,   // the device flagged the frame (malformed stream, FIFO overflow)
  inconsistent,    // a line was found but is not a tape of the configured size at the
                   // configured ceiling height (width, coverage, contrast, band shape)
  jump,            // Navigator tracking: farther from the previous pose than the robot can move
};

std::string_view to_string(Status s);

}  // namespace ceilnav::host
