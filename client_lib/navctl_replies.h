#pragma once
// What navctl prints of navd's replies: lines for people, or with --json one JSON object each.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "navd/v1/localization.pb.h"
#include "navd/v1/mapping.pb.h"
#include "navd/v1/navigation.pb.h"
#include "navd/v1/planning.pb.h"

namespace navd::navctl {

// `navctl plan --json`'s object, the same from navd and offline; `points` are gRPC's or Eigen's
// (anything with x() and y(), metres in the map frame).
template <typename Points>
nlohmann::json PlanJson(const std::string& planner, double length, double planning_time, uint64_t expansions,
                        const Points& points) {
  nlohmann::json path = nlohmann::json::array();
  for (const auto& p : points) path.push_back({p.x(), p.y()});
  return {{"planner", planner},
          {"length", length},
          {"planning_time", planning_time},
          {"expansions", expansions},
          {"path", path}};
}

void PrintPath(const v1::ComputePathResponse& r, bool json_out);
void PrintPlanners(const v1::ListPlannersResponse& r, bool json_out);
void PrintNavigationResult(const v1::NavigationResult& result, bool json_out);
void PrintPose(const v1::GetPoseResponse& r, bool json_out);
void PrintStatus(const v1::GetStatusResponse& s, bool json_out);
void PrintSpeedZones(const v1::SpeedZones& zones, bool json_out);
void PrintMapInfo(const v1::MapInfo& m, bool json_out);
void PrintMappingStatus(const v1::MappingStatus& st, bool json_out);

// navctl speed-zones --set's NAME:X_MIN,Y_MIN,X_MAX,Y_MAX:MAX_SPEED boxes (map frame, metres, m/s)
// as a request; throws std::runtime_error or std::invalid_argument naming the malformed spec.
v1::SetSpeedZonesRequest ParseSpeedZones(const std::vector<std::string>& zone_specs);

}  // namespace navd::navctl
