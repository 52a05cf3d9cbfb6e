#pragma once
// The one quality knob: named levels that move a bake along the speed/accuracy front, all
// passes together (`--quality`, a scene file's `[bake] quality`, the viewer's panel). What
// each level sets: bake/pipeline/bake.h (apply_quality); what it costs and gains:
// docs/speed-accuracy.md ("Quality levels").

#include <string>

namespace lb {

enum class Quality { draft, standard, high, final };

const char* to_string(Quality quality);
// "draft", "standard", "high" or "final"; throws std::invalid_argument naming them.
Quality parse_quality(const std::string& name);

}  // namespace lb
