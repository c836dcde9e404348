#include "services/common/sonar_ring.h"

namespace navd {

const std::vector<double>& PioneerSonarAngles() {
  static const std::vector<double> angles = [] {
    std::vector<double> a;
    for (double deg : {90, 50, 30, 10, -10, -30, -50, -90, -90, -130, -150, -170, 170, 150, 130, 90}) {
      a.push_back(deg * M_PI / 180.0);
    }
    return a;
  }();
  return angles;
}

}  // namespace navd
