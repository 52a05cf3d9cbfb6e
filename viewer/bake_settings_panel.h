#pragma once
// The bake's settings in the viewer's panel, drawn from the same table as the command line and
// scene files (bake/pipeline/bake_settings.h): the ones a quality level sets and the seed
// first, every other one under "more settings", each clamped to its range.

#include "bake/pipeline/bake_settings.h"

namespace lb {

// Draws the widgets in the current ImGui window; returns true when a value changed.
bool bake_settings_panel(BakeParams& params);

}  // namespace lb
