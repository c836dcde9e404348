#include "services/mapping/pose_graph_g2o.h"

#include <cstdio>

#include "services/common/error.h"

namespace navd::mapping {

std::string FormatG2o(const PoseGraph& graph, const std::vector<int>& vertex_ids) {
  if (vertex_ids.size() != graph.nodes().size())
    throw Error(ErrorCode::kInvalidArgument, "g2o vertex ids: " + std::to_string(vertex_ids.size()) + " for " +
                                                 std::to_string(graph.nodes().size()) + " nodes");
  std::string out;
  char line[320];
  for (size_t n = 0; n < graph.nodes().size(); ++n) {
    const Pose2& p = graph.nodes()[n];
    std::snprintf(line, sizeof line, "VERTEX_SE2 %d %.6f %.6f %.9f\n", vertex_ids[n], p.x, p.y, p.theta);
    out += line;
  }
  for (const PoseGraphEdge& e : graph.edges()) {
    const Eigen::Matrix3d& i = e.information;
    std::snprintf(line, sizeof line, "EDGE_SE2 %d %d %.6f %.6f %.9f %.6g %.6g %.6g %.6g %.6g %.6g\n",
                  vertex_ids[e.from], vertex_ids[e.to], e.measurement.x, e.measurement.y, e.measurement.theta, i(0, 0),
                  i(0, 1), i(0, 2), i(1, 1), i(1, 2), i(2, 2));
    out += line;
  }
  return out;
}

}  // namespace navd::mapping
