#pragma once

#include <numbers>

namespace lb {

// Pi as the float the samplers and light models use, defined once so that files compiled
// together (unity builds) and apart agree on one name and one value.
inline constexpr float kPi = std::numbers::pi_v<float>;

}  // namespace lb
