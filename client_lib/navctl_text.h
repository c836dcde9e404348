#pragma once
// navctl's command-line text: naming navd's enums, poses as JSON. Pose tuples: services/common/pose_text.h.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "navd/v1/navigation.pb.h"
#include "services/common/pose_text.h"

namespace navd::navctl {

using navd::ParseTuple;
using navd::ParseTupleList;

nlohmann::json PoseJson(const v1::Pose2D& p);
const char* OutcomeText(v1::Outcome o);
const char* StateText(v1::NavigationState s);

}  // namespace navd::navctl
