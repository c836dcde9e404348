#pragma once
// A pose graph in g2o's text format (that of g2o's 2-D examples and of the public SLAM benchmarks'
// graph files), to look at a run's graph in g2o_viewer or optimise it with another solver:
//   VERTEX_SE2 id x y theta
//   EDGE_SE2 from to dx dy dtheta i11 i12 i13 i22 i23 i33
// Vertex poses are in the map frame (m, rad); an edge's measurement is its `to` vertex in its
// `from` vertex's frame, and its information the upper triangle of the edge's 3 x 3 information
// (x, y in 1/m², theta in 1/rad²) in the frame g2o's EDGE_SE2 measures its error in, `to`'s, as
// PoseGraph's. The file has no room for a per-edge kernel: the Cauchy kernel on navd's loop edges
// is not in it (g2o applies a kernel to every edge or none).
#include <string>
#include <vector>

#include "services/mapping/pose_graph.h"

namespace navd::mapping {

// `vertex_ids[n]` is node n's id in the file (navd-replay writes the scan each node was made from,
// so the ids are the log's scans). Throws Error(kInvalidArgument) when the ids are not one per
// node.
std::string FormatG2o(const PoseGraph& graph, const std::vector<int>& vertex_ids);

}  // namespace navd::mapping
