#include "host/status.hpp"

namespace ceilnav::host {

std::string_view to_string(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::no_tape:
      return "no_tape";
    case Status::too_few_points:
      return "too_few_points";
    case Status::degenerate:
      return "degenerate";
    case Status::bad_config:
      return "bad_config";
    case Status::frame_invalid:
      return "frame_invalid";
    case Status::inconsistent:
      return "inconsistent";
    case Status::jump:
      return "jump";
  }
  return "unknown";
}

}  // namespace ceilnav::host
