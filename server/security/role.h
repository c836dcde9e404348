#pragma once
// Who may call what on navd's gRPC API. Roles are ordered: each may do what the ones below it may.
//   viewer:   reads (Get*, List*, Stream*, status)
//   operator: also moves the robot (ComputePath, navigation and missions, exploration)
//   admin:    also changes what the robot believes or serves (LoadMap, SaveMap, SetPose, mapping,
//             localiser choice, speed zones)
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace navd::server::security {

enum class Role { kViewer = 0, kOperator = 1, kAdmin = 2 };

const char* RoleName(Role role);
// "viewer" | "operator" | "admin"; nullopt for anything else.
std::optional<Role> ParseRole(std::string_view name);

// What a call to `method_path` ("/package.Service/Method", as gRPC's :path) needs:
//   nullopt for calls open to everyone (grpc.health.v1, so that probes need no credentials);
//   the method's role for navd's own methods; kAdmin for any method this table does not know,
//   so that a method added without a role here is closed rather than open.
std::optional<Role> RequiredRole(std::string_view method_path);

// Every navd method this table names, as "/package.Service/Method" (for tests that compare it
// with the services' descriptors).
std::vector<std::string> MethodsWithRoles();

}  // namespace navd::server::security
