#pragma once
// The costmap navd plans on as viewers should see it: the served map's costmap with the cells the
// depth camera's obstacle layer holds drawn in and inflated, Nav2's master costmap (a leg plan
// gets the same, less the cells within the inflation of its goal). Rebuilt only when the map's costmap or the layer
// changed; thread-safe, for the DDS publisher and the live view.
#include <memory>
#include <mutex>

#include "services/perception/depth_obstacle_layer.h"
#include "services/planning/planning_engine.h"

namespace navd::server {

class SensedCostmap {
 public:
  // layer: null when there is no depth camera (the map's costmap as it is).
  SensedCostmap(planning::PlanningEngine& planning, const perception::DepthObstacleLayer* layer)
      : planning_(planning), layer_(layer) {}
  // Null before the planner has a costmap.
  std::shared_ptr<const planning::Costmap> Current();

 private:
  planning::PlanningEngine& planning_;
  const perception::DepthObstacleLayer* layer_;
  std::mutex mutex_;
  std::shared_ptr<const planning::Costmap> base_, current_;
  uint64_t layer_version_ = 0;
};

}  // namespace navd::server
