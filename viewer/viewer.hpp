// The viewer's one entry header for the shells (`shprt view` in tools/, the paper study's display
// rate in bench/paper): the window (viewer_app.hpp), the headless benchmark (benchmark.hpp), the
// light rig's parsing (light_rig.hpp) and the screenshot writer (screenshot.hpp). Nothing outside
// viewer/ includes another of its headers (DESIGN.md: "A shell includes the viewer only through
// its one entry header").
#pragma once

#include "benchmark.hpp"
#include "light_rig.hpp"
#include "screenshot.hpp"
#include "viewer_app.hpp"
