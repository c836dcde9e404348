#pragma once
// Poses typed on a command line (navctl, navsim): "X,Y" or "X,Y,THETA", metres and radians.
#include <string>
#include <vector>

namespace navd {

// Parses "X,Y" or "X,Y,THETA" (numbers; "nan"/"inf" pass through for navd to reject). Throws
// std::invalid_argument naming `flag`.
std::vector<double> ParseTuple(const std::string& text, const std::string& flag, size_t min, size_t max);
// "X,Y[,THETA];X,Y[,THETA];..." into poses (theta 0 when left out); `has_heading` reports whether
// any waypoint gave one.
std::vector<std::vector<double>> ParseTupleList(const std::string& text, const std::string& flag, bool* has_heading);

}  // namespace navd
