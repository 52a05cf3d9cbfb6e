#include "viewer/render_settings.h"

#include <stdexcept>

namespace lb {

namespace {
constexpr const char* kTermNames[] = {"all",     "direct",      "caustic", "radiosity",
                                      "ambient", "specular",    "normals", "texel_density",
                                      "patches", "reflectance", "baked"};
}

const char* to_string(Term term) {
  return kTermNames[int(term)];
}

std::vector<std::string> term_names() {
  return std::vector<std::string>(std::begin(kTermNames), std::end(kTermNames));
}

Term parse_term(const std::string& name) {
  for (int i = 0; i < int(std::size(kTermNames)); ++i) {
    if (name == kTermNames[i]) return Term(i);
  }
  std::string list;
  for (const char* n : kTermNames) list += std::string(list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown term '" + name + "' (expected one of " + list + ")");
}

const char* to_string(DirectMode mode) {
  return mode == DirectMode::full ? "full" : "stochastic";
}

DirectMode parse_direct_mode(const std::string& name) {
  if (name == "full") return DirectMode::full;
  if (name == "stochastic") return DirectMode::stochastic;
  throw std::invalid_argument("unknown direct light mode '" + name +
                              "' (expected full or stochastic)");
}

RenderSettings figure8_preset(int index, RenderSettings base) {
  base.term = Term::all;
  base.direct = true;
  base.ambient = index == 1;
  base.radiosity = index >= 2;
  base.caustics = index >= 3;
  return base;
}

const char* figure8_preset_name(int index) {
  switch (index) {
    case 0:
      return "direct only";
    case 1:
      return "direct + constant ambient (Whitted)";
    case 2:
      return "direct + radiosity";
    case 3:
      return "direct + radiosity + caustic maps";
  }
  return "?";
}

}  // namespace lb
