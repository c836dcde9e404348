#pragma once
// navctl's command-line text: parsing pose tuples and naming navd's enums.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "navd/v1/navigation.pb.h"

namespace navd::navctl {

// Parses "X,Y" or "X,Y,THETA" (numbers; "nan"/"inf" pass through for navd to reject). Throws
// std::invalid_argument naming `flag`.
std::vector<double> ParseTuple(const std::string& text, const std::string& flag, size_t min, size_t max);
// "X,Y[,THETA];X,Y[,THETA];..." into poses (theta 0 when left out); `has_heading` reports whether
// any waypoint gave one.
std::vector<std::vector<double>> ParseTupleList(const std::string& text, const std::string& flag, bool* has_heading);

nlohmann::json PoseJson(const v1::Pose2D& p);
const char* OutcomeText(v1::Outcome o);
const char* StateText(v1::NavigationState s);

}  // namespace navd::navctl
