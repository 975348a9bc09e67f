#include "stream/version.hpp"
namespace ceilnav::golden { const char* golden_tag() { return version_string(); } }
