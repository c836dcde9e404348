#include "services/mapping/shared_places.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"
#include "services/mapping/cell_key.h"

namespace navd::mapping {

SharedPlaces::SharedPlaces(double radius) : radius_(radius) {
  if (!(std::isfinite(radius) && radius > 0.0))
    throw Error(ErrorCode::kInvalidArgument, "seen_through_support must be a finite distance above 0");
}

int64_t SharedPlaces::Key(const Point2& p, int dx, int dy) const {
  return CellKey(static_cast<int64_t>(std::floor(p.x() / radius_)) + dx,
                 static_cast<int64_t>(std::floor(p.y() / radius_)) + dy);
}

void SharedPlaces::Add(const Point2& point, int scan) {
  entries_.push_back({Key(point, 0, 0), point, scan});
  sorted_ = false;
}

bool SharedPlaces::SeenByAnother(const Point2& point, int scan) {
  if (!sorted_) {
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.cell < b.cell; });
    sorted_ = true;
  }
  auto by_cell = [](const Entry& e, int64_t cell) { return e.cell < cell; };
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const int64_t cell = Key(point, dx, dy);
      for (auto it = std::lower_bound(entries_.begin(), entries_.end(), cell, by_cell);
           it != entries_.end() && it->cell == cell; ++it)
        if (it->scan != scan && (it->point - point).squaredNorm() < radius_ * radius_) return true;
    }
  return false;
}

}  // namespace navd::mapping
