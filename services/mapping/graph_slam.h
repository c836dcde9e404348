#pragma once
// Graph SLAM with a correlative scan-matching front end and a pose-graph back end (the design of
// Karto and slam_toolbox, with Cartographer's "submap" as the recent scans):
//  - each scan is matched against a local map made of the node scans of the last few metres,
//    around the odometry prediction (CorrelativeScanMatcher): the match is the node's pose and
//    the edge to the previous node; where odometry errs beyond that window, FrontEndRecovery
//    searches a poorly matched scan again wider (when its options turn it on);
//  - each new node looks for a loop: the nearest old node (farther back along the chain than the
//    local map reaches) within a search radius; the new scan is matched against that node's
//    neighbourhood over a wide window, coarse (10 cm) then fine (5 cm); a match that explains
//    enough of the scan becomes a robust (Cauchy) edge and the graph is optimised;
//  - every match is polished by point-to-line matching of all the scan's returns against the same
//    reference points (PointToLineMatcher), which holds it to the walls closer than the
//    correlative grid's cells;
//  - the map re-renders from the optimised poses (OccupancyGridMapper).
// Map frame: the first scan sits at options.first_pose (the origin by default); metres, radians.
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "services/common/occupancy_grid.h"
#include "services/common/odometry_noise.h"
#include "services/common/pose2.h"
#include "services/common/scan_reach.h"
#include "services/mapping/correlative_scan_matcher.h"
#include "services/mapping/front_end_recovery.h"
#include "services/mapping/odometry_bias.h"
#include "services/mapping/occupancy_grid_mapper.h"
#include "services/mapping/point_to_line_matcher.h"
#include "services/mapping/pose_graph.h"
#include "services/mapping/seen_through_check.h"

namespace navd::mapping {

// A laser scan as recorded: ranges (m) at angle_min + i * increment in the robot frame.
struct RangeScan {
  std::vector<float> ranges;
  double angle_min = 0.0, angle_increment = 0.0;
  double stamp = 0.0;
  double range_max = std::numeric_limits<double>::infinity();  // readings here or beyond: no return
};

struct GraphSlamOptions {
  Pose2 first_pose;                // the first scan's pose in the map frame
  double usable_range = 20.0;      // m: longer readings are no-returns for matching, except
  double far_usable_range = 50.0;  // in a scan with fewer than min_near_echoes within usable_range
  int min_near_echoes = 60;        // (an open hall's; of 361 beams, a share beyond): then this far (ScanReach)
  // As a reference (the local map, a loop closure's candidate), a node's scan reaches this much
  // further than usable_range, where it is matched: a wall a scan sees near the cut was seen by
  // the nodes before it from elsewhere, often just beyond their own cut, and would be missing
  // from the reference where the scan's far echoes need it (a hall's walls 10-30 m off). Scans
  // cut at far_usable_range reach no further.
  double reference_extra_range = 10.0;  // m
  double match_point_spacing = 0.1;     // m between the scan points matched
  // A scan's returns are thinned to no fewer than this many (ThinPointsTo, up to
  // match_point_spacing apart) before anything uses them: a scanner of a thousand beams or a whole
  // turn costs about what a half-degree 180-degree scanner's beams do, and one with fewer beams
  // keeps them all.
  size_t return_budget = kSickHalfDegreeBeams;
  // The local map: the last local_map_nodes nodes, and as many more (up to local_map_max_nodes,
  // no more than loop closing's loop_min_node_gap) as lie within local_map_travel m of chain. A
  // log with a scan every 0.5-1 m has its 4 m in 8 nodes; one with a scan every 10 cm (a node
  // every 20 cm) would otherwise match against the last 1.6 m only, where each node adds its
  // small error to the next.
  int local_map_nodes = 8;
  double local_map_travel = 4.0;  // m
  int local_map_max_nodes = 30;
  // When on, a node's reference points that another node of the local map it joins saw through
  // (people walking past, SeenThroughCheck) are left out of every reference (local map, loop
  // closure, refinement), unless a point of another node of that local map lies within
  // seen_through_support: what two nodes saw in one place stood still (a pole or a table's leg,
  // which the beams of a third sometimes pass). Off by default: it holds a bare corridor that
  // people walk, but where the real logs' scans see through a place for other reasons (glass,
  // grazing beams) it leaves out what the front end needed, and on a robot's own odometry without
  // FrontEndRecovery the chain can break (docs/results.md).
  bool drop_seen_through = false;
  SeenThroughOptions seen_through;
  double seen_through_support = 0.15;  // m
  double node_travel = 0.2;            // m, or
  double node_turn = 0.2;              // rad, of odometry since the last node make a new node
  // The front end's window (defaults: ±0.25 m, ±0.15 rad), with a mild prior on the odometry's
  // prediction so a scan in a corridor does not slide along it.
  ScanMatchOptions sequential = [] {
    ScanMatchOptions s;
    s.prior_sigma_xy = 0.15;
    s.prior_sigma_theta = 0.15;
    return s;
  }();
  // The odometry's noise (the model of services/common/odometry_noise.h: T of each step's
  // translation, R rad of heading per metre driven, T of each turn). Its error grows with the motion
  // since the last node, so the window and its prior widen with it wherever these exceed the base:
  // to front_window_sigmas_xy x T x travel (m), and to front_window_sigmas_heading x R x travel +
  // front_window_sigmas_turn x T x |turn| (rad). A log with scans metres apart, or turning a right
  // angle between two scans, needs that; one sampled every few centimetres keeps the base window.
  // Odometry noisier than the default needs the window as much wider: a scan whose true heading
  // lies beyond the window fits a wrong one, and the chain bends there. The turn's share is held to
  // two sigma: a wider turn window lets a scan in an open hall, whose walls are far and sparse, turn
  // onto the wrong wall.
  OdometryNoise odometry;
  double front_window_sigmas_xy = 4.0;
  double front_window_sigmas_heading = 3.0;
  double front_window_sigmas_turn = 2.0;
  // The odometry's systematic error (OdometryBias), learnt from the steps whose walls fixed the
  // match: along the step's travel, or about its heading, the walls' share of the polish's
  // information (WallShareOf; the rest is its prior, which holds the correlative pose) is at least
  // bias_min_wall_share.
  OdometryBiasOptions odometry_bias;
  double bias_min_wall_share = 0.5;
  // Odometry that errs beyond that window (FrontEndRecovery): off unless below_score is set.
  FrontEndRecoveryOptions front_recovery;
  // The front end's edge: at least this uncertain in every direction, and more where the walls the
  // scan matched leave its pose free (along a bare corridor, or an open hall's far, sparse walls):
  // there, the polish's pair information (PointToLineResult::mean_information) is small, and the
  // pose is held only by the odometry's prior, as uncertain as sequential_free_sigma_*. The
  // covariances add: a well-matched edge ends a little looser than the base (about 0.04 m), a
  // corridor's as loose as the odometry along it, and a loop closure bends the chain where its
  // matches were weak rather than evenly.
  double sequential_sigma_xy = 0.03, sequential_sigma_theta = 0.01;           // m, rad
  double sequential_free_sigma_xy = 0.1, sequential_free_sigma_theta = 0.05;  // m, rad
  // Every match (front end, loop closure, refinement) is polished by point-to-line matching
  // against the same reference points; a polish that moves the pose farther than this paired
  // points with the wrong walls, and the correlative pose stands.
  PointToLineOptions polish;
  double polish_max_shift_xy = 0.05;     // m
  double polish_max_shift_theta = 0.03;  // rad
  // Matches against another pass (loop closures, refinement) start from a coarser search over a
  // wider window, so their polish holds less to where it started: only where no wall constrains
  // the pose (a bare corridor) should the start win. The front end's firmer prior keeps a scan in
  // an open hall, whose few walls are far and sparse, from sliding.
  PointToLineOptions loop_polish = [] {
    PointToLineOptions p;
    p.prior_sigma_xy = 0.3;
    return p;
  }();
  // Loop closing.
  double loop_search_radius = 4.0;  // m between the new node and a candidate
  int loop_min_node_gap = 30;       // nodes back along the chain, at least
  int loop_neighbourhood = 5;       // candidate's neighbours either side forming its map
  double loop_window_xy = 3.0, loop_window_theta = 0.4;
  double loop_min_score = 0.66;  // mean lookup value of the scan on the candidate's map
  // Scans with fewer matched points (0.1 m apart) close no loops: a robot turning in a tight
  // corner sees a small, nearly round outline that matches at many headings.
  int loop_min_points = 50;
  // The most a closure may move the new node: drift grows with the distance driven since the
  // last closure, so the gate does too.
  double loop_max_correction = 0.15;        // m, plus
  double loop_correction_per_metre = 0.02;  // of travel since the last accepted closure
  // Refused as ambiguous when a pose at least loop_distinct_xy away scores within this fraction
  // of the best (corridors, rows of identical rooms).
  double loop_distinct_xy = 0.5;
  double loop_distinct_theta = 0.1;  // rad: turned this far is another pose too
  double loop_max_ambiguity = 0.9;
  // A closure found no nearer than the drift since the last closure allows is searched again as
  // far as the chain can have drifted since it left the candidate, up to loop_wide_max_correction
  // (m): back at the end of a loop whose closures on the way did not hold the graph rigid. That
  // wider search begins on a 20 cm grid, whose broad peaks read more alike, so it refuses
  // ambiguity from loop_wide_max_ambiguity.
  double loop_wide_max_correction = 1.0;
  double loop_wide_max_ambiguity = 0.85;
  double loop_sigma_xy = 0.05, loop_sigma_theta = 0.02;
  // The graph is optimised once the closures added since it last was disagree with it by more
  // than this, in all (the sum of their squared errors whitened by the loop sigmas). A robot back
  // in a place it has mapped closes a loop at nearly every node, each within a fraction of a sigma
  // of the graph; optimising the whole graph for each would make the time per scan grow with the log.
  double loop_settled_error = 1.0;
  // Refused when more than this share of the new scan's returns near the candidate's, at the
  // matched pose, see their wall from the other side (SurfaceFacingCheck).
  double loop_max_behind = 0.5;
  // Refinement (Refine()): once the graph is consistent, every node is matched again against
  // each stretch of the chain passing near it, in a narrow window around where the graph puts it
  // (a partial match, refine_min_partial_score, holds it only where its walls do).
  // The many small constraints average out the front end's per-step errors the way Cartographer's
  // constraints to every nearby submap do.
  double refine_radius = 3.0;         // m between the node and the nearest node of a stretch
  double refine_window_xy = 0.2;      // m
  double refine_window_theta = 0.08;  // rad
  int refine_passes = 2;
  int refine_max_stretches = 3;  // the nearest stretches matched per node
  // Nodes where the robot turned on the spot (this far in rad, over at most refine_spot_travel m
  // since the previous node) are left out of refinement: a scan swept while turning fast is
  // skewed, and fits the other pass best at a wrong heading.
  double refine_spot_turn = 0.5;
  double refine_spot_travel = 0.35;
  double refine_max_spread = 0.1;  // m: a match that slides farther along a corridor is partial
  // A match explaining less than loop_min_score of the node's scan (a corridor driven the other
  // way: a 180-degree scanner sees in common only the walls beside the robot), but at least this
  // much, or one that slides along a corridor, is partial: it holds the node only as far as the
  // walls its polish paired with fix it, across the corridor and not along it, and where they
  // leave it free, as uncertain as refine_partial_free_sigma (m and rad).
  double refine_min_partial_score = 0.3;
  double refine_partial_free_sigma = 0.2;
  PoseGraphOptions optimizer;
};

// An accepted loop closure: scans by their order of arrival, the matched pose of `to_scan` in
// `from_scan`'s frame, the match's score and the information its edge holds it with (in
// `to_scan`'s frame: x, y in 1/m², theta in 1/rad²; a partial refinement match's is small along
// the corridor, where it measures nothing).
struct LoopClosure {
  int from_scan = 0, to_scan = 0;
  Pose2 measurement;
  double score = 0.0;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
};

class GraphSlam {
 public:
  // Throws Error(kInvalidArgument) for options it cannot run with (front_recovery's, or with
  // drop_seen_through a seen_through_support that is no distance above 0).
  explicit GraphSlam(const GraphSlamOptions& options = {});

  // Adds a scan taken at odometry pose `odometry` (any fixed frame); returns the scan's pose in
  // the map frame as estimated now.
  Pose2 AddScan(const Pose2& odometry, const RangeScan& scan);

  // Matches every node against the other stretches of the chain near it, adds each good match as
  // a robust edge and re-optimises (refine_passes times, each from the poses the last one left).
  // For the end of a run: it costs about a loop-closure match per node and stretch.
  void Refine();

  // Every scan's pose as the graph stands now (nodes optimised, scans between nodes carried by
  // their odometry from the node before), in the order added.
  std::vector<Pose2> Trajectory() const;
  int loop_closures() const { return static_cast<int>(closures_.size()); }
  const std::vector<LoopClosure>& closures() const { return closures_; }
  int loop_attempts() const { return loop_attempts_; }
  // The odometry's systematic error as learnt so far.
  const OdometryBias& odometry_bias() const { return odometry_bias_; }
  // How often the graph was optimised: for closures (loop_settled_error) and by Refine().
  int optimisations() const { return optimisations_; }
  // The matches the last Refine() pass added, as closures.
  const std::vector<LoopClosure>& refinements() const { return refinements_; }
  int nodes() const { return static_cast<int>(graph_.nodes().size()); }
  // The reference points left out as seen through (drop_seen_through), map frame, at the nodes'
  // poses now.
  std::vector<Point2> SeenThroughPoints() const;
  // The occupancy grid of every node's scan at its optimised pose, at options.resolution unless the
  // nodes spread wider than a grid holds at it (ResolutionToFit).
  OccupancyGrid RenderMap(const MapperOptions& options) const;
  // The same into a mapper of the caller's extent.
  void RenderInto(OccupancyGridMapper& mapper) const;
  // The latest node's pose and scan (for incremental maps), or nullptr before the first scan.
  const RangeScan* last_node_scan() const { return node_scans_.empty() ? nullptr : &node_scans_.back(); }
  Pose2 last_node_pose() const { return graph_.nodes().empty() ? Pose2{} : graph_.nodes().back(); }
  const PoseGraph& graph() const { return graph_; }
  // The scan each node was made from (by order of arrival), node by node.
  const std::vector<int>& node_scan_indices() const { return node_scan_; }

 private:
  // The scan's returns (robot frame, beam order, no-returns dropped): those matched, within its
  // reach (ScanReach), and those it offers as a reference, reference_extra_range further.
  struct NodeReturns {
    std::vector<Point2> matched, reference;
  };
  NodeReturns Returns(const RangeScan& scan) const;
  std::vector<Point2> NodePointsInMap(int first, int last) const;
  // Marks the reference points of `node` and of the local map before it that the other saw
  // through (drop_seen_through).
  void MarkSeenThrough(int node);
  // The first node of the local map that ends at node `last`.
  int LocalMapFirst(int last) const;
  // The front end's search window for a scan `moved` (odometry) from the last node.
  ScanMatchOptions FrontEndWindow(const Pose2& moved) const;
  // The information of an edge to a node matched at `pose` (the edge's error frame: the node's),
  // at least as uncertain as sigma_xy (m), sigma_theta (rad) in every direction, and where the
  // walls the polish paired with (their mean pair information `matched`, map frame) leave the pose
  // free, as uncertain as free_sigma_xy, free_sigma_theta. Zero `matched` (the polish was
  // refused): the base alone.
  static Eigen::Matrix3d WallInformation(const Pose2& pose, const Eigen::Matrix3d& matched, double sigma_xy,
                                         double sigma_theta, double free_sigma_xy, double free_sigma_theta);
  // Teaches odometry_bias_ the odometry's `step` from node `last` against the matched pose of the
  // new node, as far as the polish's information `matched` (map frame; zero: no polish) says the
  // walls fixed it.
  void LearnOdometryBias(int last, const Pose2& step, const Pose2& pose, const Eigen::Matrix3d& matched);
  void TryLoopClosure(int node);
  // The graph optimised with every edge so far; the closures' unsettled error starts again.
  void Optimize();
  // The candidate's neighbourhood as a loop closure searches it: its points (map frame) and their
  // correlation grids, each built at its first use, so the wide retry reuses the fine grid and the
  // 10 cm one.
  struct LoopReference {
    std::vector<Point2> points;
    std::array<std::optional<CorrelationGrid>, 3> grids;  // by resolution: the front end's, twice, four times
    const CorrelationGrid& Grid(int level, const ScanMatchOptions& base) {
      const double scale = 1 << level;
      auto& grid = grids.at(level);
      if (!grid) grid.emplace(points, base.resolution * scale, base.sigma * scale);
      return *grid;
    }
  };
  // `scan` (node's points, thinned) against `reference` for a correction up to `allowance` (m): the
  // coarse search (`wide`: beginning on a 20 cm grid), the fine one, the score and ambiguity tests,
  // the polish and the gate. True with the matched pose of `node` in `match`.
  bool LoopMatch(LoopReference& reference, const std::vector<Point2>& scan, int node, double allowance, bool wide,
                 ScanMatch* match) const;
  // The loop closure's coarse search around `here` for a correction up to `allowance` (m): on a
  // 10 cm grid, or with `wide_first` first on a 20 cm one. `ambiguity` receives the match that
  // judged the whole window (its coarse_best and coarse_elsewhere).
  ScanMatch CoarseLoopMatch(LoopReference& reference, const std::vector<Point2>& scan, const Pose2& here,
                            double allowance, bool wide_first, ScanMatch* ambiguity) const;
  // The share of `returns` (robot frame, beam order) at `pose` seeing the walls of nodes
  // first..last from behind.
  double BehindShare(int first, int last, const std::vector<Point2>& returns, const Pose2& pose) const;
  bool TurnedOnTheSpot(int node) const;
  // `guess` polished by point-to-line matching of `returns` (robot frame) on `reference` (map
  // frame). The polish takes every return of the scan, not the thinned sample the correlative
  // search scores: each point on a wall is one more measurement of where that wall lies.
  // `information`, when given, receives the polish's mean pair information (zero when the polish
  // was refused).
  Pose2 Polish(std::vector<Point2> reference, const std::vector<Point2>& returns, const Pose2& guess,
               const PointToLineOptions& options, Eigen::Matrix3d* information = nullptr) const;
  // A scan's points (robot frame, thinned) matched against `reference` (map frame) around `guess`,
  // then polished with all its `returns`. A match that explains too little (below loop_min_score)
  // or slides along a corridor is partial: from at least refine_min_partial_score, the polish from
  // `guess` alone stands, and `walls` receives its mean pair information (zero for a whole
  // match). False when there is no match, whole or partial.
  bool MatchAgainst(const std::vector<Point2>& scan, const std::vector<Point2>& returns, std::vector<Point2> reference,
                    const Pose2& guess, const ScanMatchOptions& window, ScanMatch* match, Eigen::Matrix3d* walls) const;

  GraphSlamOptions o_;
  FrontEndRecovery recovery_;
  OdometryBias odometry_bias_;
  PoseGraph graph_;
  double unsettled_error_ = 0.0;  // of the closures added since the graph was last optimised
  int optimisations_ = 0;
  std::vector<RangeScan> node_scans_;
  std::vector<std::vector<Point2>> node_points_;            // robot frame, as matched
  std::vector<std::vector<Point2>> node_reference_points_;  // robot frame, as a reference (further)
  // Per node, per reference point: another node saw through it (drop_seen_through).
  std::vector<std::vector<char>> node_seen_through_;
  std::vector<Pose2> node_odometry_;
  std::vector<double> node_distance_;  // m along the chain from the first node, as the front end placed them
  std::vector<int> node_scan_;         // the scan each node was made from
  // Per scan added: its node, and its odometry offset from that node.
  std::vector<int> scan_node_;
  std::vector<Pose2> scan_offset_;
  int held_scan_ = -1;  // the last scan the front end held back (FrontEndRecovery)
  std::vector<LoopClosure> closures_;
  std::vector<LoopClosure> refinements_;
  double travel_since_closure_ = 0.0;  // m
  int loop_attempts_ = 0;
};

}  // namespace navd::mapping
