#include "bake/quality.h"

#include <stdexcept>

namespace lb {

const char* to_string(Quality quality) {
  switch (quality) {
    case Quality::draft:
      return "draft";
    case Quality::standard:
      return "standard";
    case Quality::high:
      return "high";
    case Quality::final:
      return "final";
  }
  return "standard";
}

Quality parse_quality(const std::string& name) {
  for (Quality q : {Quality::draft, Quality::standard, Quality::high, Quality::final})
    if (name == to_string(q)) return q;
  throw std::invalid_argument("quality is draft, standard, high or final, not '" + name + "'");
}

}  // namespace lb
