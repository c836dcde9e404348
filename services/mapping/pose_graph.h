#pragma once
// An SE(2) pose graph and its least-squares optimiser (the back end of graph SLAM, as in Karto's
// SPA solver and g2o's 2-D examples): nodes are robot poses, edges measured relative poses with
// an information matrix; Gauss-Newton iterations solve the sparse normal equations with Eigen's
// SimplicialLDLT. Loop-closure edges can carry a robust kernel (Cauchy), so a wrong closure that
// slipped past the front end pulls weakly instead of bending the whole map. Map frame, metres,
// radians.
#include <Eigen/Core>
#include <vector>

#include "services/common/pose2.h"

namespace navd::mapping {

struct PoseGraphEdge {
  int from = 0, to = 0;
  Pose2 measurement;  // pose of `to` in `from`'s frame
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  bool robust = false;  // Cauchy kernel (loop closures)
};

struct PoseGraphOptions {
  int max_iterations = 20;
  // The Cauchy kernel's c, on the whitened error (units of sigma). Three sigma: the first closure
  // after a long drive disagrees with the chain by many sigma and must still pull it round; a
  // kernel that halves the weight at one sigma left such a closure almost unheard.
  double cauchy_scale = 3.0;
  double converged_step = 1e-6;
};

class PoseGraph {
 public:
  int AddNode(const Pose2& pose);
  void AddEdge(const PoseGraphEdge& edge);
  // The edge's squared error whitened by its information (no kernel), at the nodes as they stand.
  double SquaredError(const PoseGraphEdge& edge) const;
  // Node 0 stays fixed (the map's anchor). Returns the final weighted squared error.
  double Optimize(const PoseGraphOptions& options = {});

  const std::vector<Pose2>& nodes() const { return nodes_; }
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  void SetNode(int i, const Pose2& pose) { nodes_[i] = pose; }
  // Keeps the first `count` edges (drops those added since).
  void TruncateEdges(size_t count) {
    if (count < edges_.size()) edges_.resize(count);
  }

 private:
  std::vector<Pose2> nodes_;
  std::vector<PoseGraphEdge> edges_;
};

}  // namespace navd::mapping
