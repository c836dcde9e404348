#include "services/mapping/pose_graph.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cmath>

#include "services/common/error.h"

namespace navd::mapping {
namespace {

// Error of an edge: the measurement's inverse composed with the nodes' relative pose, as (x, y, θ),
// and its Jacobians with respect to node i and node j (Grisetti et al., "A tutorial on
// graph-based SLAM", section IV).
struct Linearised {
  Eigen::Vector3d e;
  Eigen::Matrix3d A, B;
};

Linearised Linearise(const Pose2& xi, const Pose2& xj, const Pose2& z) {
  const double ci = std::cos(xi.theta), si = std::sin(xi.theta);
  const double cz = std::cos(z.theta), sz = std::sin(z.theta);
  Eigen::Matrix2d Ri, Rz, dRi;
  Ri << ci, -si, si, ci;
  Rz << cz, -sz, sz, cz;
  dRi << -si, -ci, ci, -si;  // dRi/dθi
  const Eigen::Vector2d dt(xj.x - xi.x, xj.y - xi.y);
  Linearised l;
  l.e.head<2>() = Rz.transpose() * (Ri.transpose() * dt - Eigen::Vector2d(z.x, z.y));
  l.e(2) = NormalizeAngle(xj.theta - xi.theta - z.theta);
  l.A.setZero();
  l.A.topLeftCorner<2, 2>() = -Rz.transpose() * Ri.transpose();
  l.A.block<2, 1>(0, 2) = Rz.transpose() * dRi.transpose() * dt;
  l.A(2, 2) = -1.0;
  l.B.setZero();
  l.B.topLeftCorner<2, 2>() = Rz.transpose() * Ri.transpose();
  l.B(2, 2) = 1.0;
  return l;
}

}  // namespace

int PoseGraph::AddNode(const Pose2& pose) {
  nodes_.push_back(pose);
  return static_cast<int>(nodes_.size()) - 1;
}

void PoseGraph::AddEdge(const PoseGraphEdge& edge) {
  const int n = static_cast<int>(nodes_.size());
  if (edge.from < 0 || edge.to < 0 || edge.from >= n || edge.to >= n || edge.from == edge.to)
    throw Error(ErrorCode::kInvalidArgument, "pose graph edge joins unknown or identical nodes");
  edges_.push_back(edge);
}

double PoseGraph::SquaredError(const PoseGraphEdge& edge) const {
  const Eigen::Vector3d e = Linearise(nodes_.at(edge.from), nodes_.at(edge.to), edge.measurement).e;
  return e.dot(edge.information * e);
}

double PoseGraph::Optimize(const PoseGraphOptions& o) {
  const int n = static_cast<int>(nodes_.size());
  double chi2 = 0.0;
  if (n < 2) return chi2;
  // The sparsity pattern is the edges', the same in every iteration: ordered and analysed once.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  for (int iteration = 0; iteration < o.max_iterations; ++iteration) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(edges_.size() * 36 + 3);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(3 * n);
    chi2 = 0.0;
    for (const PoseGraphEdge& edge : edges_) {
      const Linearised l = Linearise(nodes_[edge.from], nodes_[edge.to], edge.measurement);
      const double s = l.e.dot(edge.information * l.e);
      double w = 1.0;
      if (edge.robust) {
        // Cauchy: ρ(s) = c² log(1 + s/c²); iteratively reweighted by ρ'(s).
        const double c2 = o.cauchy_scale * o.cauchy_scale;
        w = 1.0 / (1.0 + s / c2);
        chi2 += c2 * std::log1p(s / c2);
      } else {
        chi2 += s;
      }
      const Eigen::Matrix3d omega = w * edge.information;
      const Eigen::Matrix3d AtO = l.A.transpose() * omega, BtO = l.B.transpose() * omega;
      const Eigen::Matrix3d Hii = AtO * l.A, Hij = AtO * l.B, Hjj = BtO * l.B;
      const int i = 3 * edge.from, j = 3 * edge.to;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          triplets.emplace_back(i + r, i + c, Hii(r, c));
          triplets.emplace_back(i + r, j + c, Hij(r, c));
          triplets.emplace_back(j + r, i + c, Hij(c, r));
          triplets.emplace_back(j + r, j + c, Hjj(r, c));
        }
      }
      b.segment<3>(i) += AtO * l.e;
      b.segment<3>(j) += BtO * l.e;
    }
    // Anchor node 0: a strong prior keeps the system positive definite.
    for (int k = 0; k < 3; ++k) triplets.emplace_back(k, k, 1e9);
    Eigen::SparseMatrix<double> H(3 * n, 3 * n);
    H.setFromTriplets(triplets.begin(), triplets.end());
    if (iteration == 0) solver.analyzePattern(H);
    solver.factorize(H);
    if (solver.info() != Eigen::Success)
      throw Error(ErrorCode::kInternal, "pose graph: the normal equations are singular");
    const Eigen::VectorXd dx = solver.solve(-b);
    double step = 0.0;
    for (int k = 0; k < n; ++k) {
      nodes_[k].x += dx(3 * k);
      nodes_[k].y += dx(3 * k + 1);
      nodes_[k].theta = NormalizeAngle(nodes_[k].theta + dx(3 * k + 2));
      step = std::max(step, dx.segment<3>(3 * k).cwiseAbs().maxCoeff());
    }
    if (step < o.converged_step) break;
  }
  return chi2;
}

}  // namespace navd::mapping
