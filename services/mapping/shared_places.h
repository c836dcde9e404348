#pragma once
// The points of several scans (map frame), each tagged with its scan: whether a scan other than a
// point's own has a point near it. What two scans saw in one place stood still there; a person
// walking past is seen by each scan somewhere else. Metres.
#include <cstdint>
#include <vector>

#include "services/common/pose2.h"

namespace navd::mapping {

class SharedPlaces {
 public:
  // Throws Error(kInvalidArgument) unless radius (m) is finite and above 0.
  explicit SharedPlaces(double radius);
  void Add(const Point2& point, int scan);
  // A point of a scan other than `scan` lies within the radius of `point`. The first query after
  // an Add sorts the points by cell.
  bool SeenByAnother(const Point2& point, int scan);

 private:
  struct Entry {
    int64_t cell;
    Point2 point;
    int scan;
  };
  int64_t Key(const Point2& p, int dx, int dy) const;
  double radius_;
  std::vector<Entry> entries_;  // by cell (of the radius) once sorted
  bool sorted_ = true;
};

}  // namespace navd::mapping
