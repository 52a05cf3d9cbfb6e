#pragma once
// The export's options on the command line (ExportSettings, bake/export/export_settings.h):
// `lightbake export` takes them all; `lightbake view` the same words as the first values of
// its Export panel, so the window's export is the command line's export.

#include <CLI/CLI.hpp>

#include "bake/export/export_settings.h"

namespace lb::app {

// `with_directional` false: the view's own --directional (bake/view the bands) decides the
// panel's directional box, so --directional and --directional-share are not added.
void add_export_options(CLI::App& cmd, ExportSettings& settings, bool with_directional = true);

}  // namespace lb::app
