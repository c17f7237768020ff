// The viewer's one entry header for the shells: `shprt view` (tools/cmd_view.cpp) builds a
// ViewRequest and runs it (view_entry.hpp); the paper study's display rate (bench/paper) runs the
// headless benchmark (benchmark.hpp) with a light rig (light_rig.hpp). The window
// (viewer_app.hpp) and the screenshot writer (screenshot.hpp) are what run_view composes. Nothing
// outside viewer/ includes another of its headers (DESIGN.md: "A shell includes the viewer only
// through its one entry header").
#pragma once

#include "benchmark.hpp"
#include "light_rig.hpp"
#include "screenshot.hpp"
#include "view_entry.hpp"
#include "viewer_app.hpp"
