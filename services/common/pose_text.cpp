#include "services/common/pose_text.h"

#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace navd {

// Parses "X,Y" or "X,Y,THETA" (numbers; "nan"/"inf" pass through for navd to reject).
std::vector<double> ParseTuple(const std::string& text, const std::string& flag, size_t min, size_t max) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || end == part.c_str() || *end != '\0') {
      throw std::invalid_argument(flag + " '" + text + "': '" + part + "' is not a number");
    }
    out.push_back(v);
  }
  if (out.size() < min || out.size() > max) {
    const std::string form = max == 2 && min == 2   ? "X,Y"
                             : max == 3 && min == 2 ? "X,Y[,THETA]"
                                                    : std::to_string(min) + " to " + std::to_string(max) + " numbers";
    throw std::invalid_argument(flag + " '" + text + "' must be " + form);
  }
  return out;
}

std::vector<std::vector<double>> ParseTupleList(const std::string& text, const std::string& flag, bool* has_heading) {
  std::vector<std::vector<double>> out;
  std::stringstream ss(text);
  std::string item;
  *has_heading = false;
  while (std::getline(ss, item, ';')) {
    if (item.empty()) continue;
    std::vector<double> t = ParseTuple(item, flag, 2, 3);
    *has_heading = *has_heading || t.size() == 3;
    t.resize(3, 0.0);
    out.push_back(t);
  }
  if (out.empty()) throw std::invalid_argument(flag + " '" + text + "' has no waypoints (X,Y;X,Y;...)");
  return out;
}

}  // namespace navd
