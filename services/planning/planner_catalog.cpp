#include "services/planning/planner_catalog.h"

#include "services/planning/convex_grid_planner.h"
#include "services/planning/dstar_lite.h"
#include "services/planning/grid_astar_planner.h"
#include "services/planning/jump_point_planner.h"
#include "services/planning/kinodynamic_planner.h"
#include "services/planning/meadow_map_planner.h"
#include "services/planning/ompl_planner.h"
#include "services/planning/path_transform_planner.h"
#include "services/planning/voronoi_fast_marching_planner.h"
#include "services/planning/theta_star_planner.h"
#include "services/planning/topological_graph_planner.h"

namespace navd::planning {

void RegisterDefaultPlanners(PlanningEngine& engine) {
  engine.Register(std::make_unique<GridAStarPlanner>(false));
  engine.Register(std::make_unique<GridAStarPlanner>(true));
  engine.Register(std::make_unique<JumpPointPlanner>());
  engine.Register(std::make_unique<ThetaStarPlanner>());
  engine.Register(std::make_unique<DStarLitePlanner>());
  engine.Register(std::make_unique<PathTransformPlanner>(true));
  engine.Register(std::make_unique<PathTransformPlanner>(false));
  engine.Register(std::make_unique<VoronoiFastMarchingPlanner>());
  // One convex decomposition per map serves the three planners built on it.
  auto convex_cells = std::make_shared<ConvexCellMapCache>();
  engine.Register(std::make_unique<ConvexGridPlanner>(convex_cells));
  engine.Register(std::make_unique<MeadowMapPlanner>(convex_cells));
  engine.Register(std::make_unique<TopologicalGraphPlanner>(convex_cells));
  for (const auto a :
       {OmplPlanner::Algorithm::kRrtConnect, OmplPlanner::Algorithm::kRrtStar, OmplPlanner::Algorithm::kPrmStar,
        OmplPlanner::Algorithm::kInformedRrtStar, OmplPlanner::Algorithm::kBitStar}) {
    engine.Register(std::make_unique<OmplPlanner>(a));
  }
  engine.Register(std::make_unique<KinodynamicPlanner>());
}

}  // namespace navd::planning
