#include "services/common/pose2.h"

#include <cstdio>

namespace navd {

std::string FormatPoint(const Point2& p) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.2f, %.2f)", p.x(), p.y());
  return buf;
}

}  // namespace navd
