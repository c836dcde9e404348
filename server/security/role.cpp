#include "server/security/role.h"

#include <array>
#include <utility>

namespace navd::server::security {
namespace {

struct MethodRole {
  std::string_view path;
  Role role;
};

// One line per RPC of proto/navd/v1. Reads are viewer; what makes the robot move is operator;
// what replaces the map, the pose or the localiser, or changes the speed limits, is admin.
constexpr std::array kMethodRoles{
    MethodRole{"/navd.v1.PlanningService/ComputePath", Role::kOperator},
    MethodRole{"/navd.v1.PlanningService/ComputePathThroughPoses", Role::kOperator},
    MethodRole{"/navd.v1.PlanningService/ListPlanners", Role::kViewer},
    MethodRole{"/navd.v1.LocalizationService/GetPose", Role::kViewer},
    MethodRole{"/navd.v1.LocalizationService/SetPose", Role::kAdmin},
    MethodRole{"/navd.v1.LocalizationService/GlobalRelocalize", Role::kAdmin},
    MethodRole{"/navd.v1.LocalizationService/ListMethods", Role::kViewer},
    MethodRole{"/navd.v1.LocalizationService/SelectMethod", Role::kAdmin},
    MethodRole{"/navd.v1.LocalizationService/StreamPose", Role::kViewer},
    MethodRole{"/navd.v1.MappingService/GetMap", Role::kViewer},
    MethodRole{"/navd.v1.MappingService/LoadMap", Role::kAdmin},
    MethodRole{"/navd.v1.MappingService/SaveMap", Role::kAdmin},
    MethodRole{"/navd.v1.MappingService/StartMapping", Role::kAdmin},
    MethodRole{"/navd.v1.MappingService/StopMapping", Role::kAdmin},
    MethodRole{"/navd.v1.MappingService/GetMappingStatus", Role::kViewer},
    MethodRole{"/navd.v1.MappingService/StreamMapUpdates", Role::kViewer},
    MethodRole{"/navd.v1.MappingService/StartExploration", Role::kOperator},
    MethodRole{"/navd.v1.MappingService/StopExploration", Role::kOperator},
    MethodRole{"/navd.v1.MappingService/GetExplorationStatus", Role::kViewer},
    MethodRole{"/navd.v1.NavigationService/NavigateTo", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/FollowWaypoints", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/Deliver", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/PlanDeliveries", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/Cancel", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/Pause", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/Resume", Role::kOperator},
    MethodRole{"/navd.v1.NavigationService/GetStatus", Role::kViewer},
    MethodRole{"/navd.v1.NavigationService/SetSpeedZones", Role::kAdmin},
    MethodRole{"/navd.v1.NavigationService/GetSpeedZones", Role::kViewer},
};

constexpr std::string_view kOpenPrefix = "/grpc.health.v1.Health/";

}  // namespace

const char* RoleName(Role role) {
  switch (role) {
    case Role::kViewer: return "viewer";
    case Role::kOperator: return "operator";
    case Role::kAdmin: return "admin";
  }
  return "admin";
}

std::optional<Role> ParseRole(std::string_view name) {
  for (Role r : {Role::kViewer, Role::kOperator, Role::kAdmin}) {
    if (name == RoleName(r)) return r;
  }
  return std::nullopt;
}

std::optional<Role> RequiredRole(std::string_view method_path) {
  if (method_path.substr(0, kOpenPrefix.size()) == kOpenPrefix) return std::nullopt;
  for (const MethodRole& m : kMethodRoles) {
    if (m.path == method_path) return m.role;
  }
  return Role::kAdmin;
}

std::vector<std::string> MethodsWithRoles() {
  std::vector<std::string> paths;
  paths.reserve(kMethodRoles.size());
  for (const MethodRole& m : kMethodRoles) paths.emplace_back(m.path);
  return paths;
}

}  // namespace navd::server::security
