// The command line's precompiled header (tools/CMakeLists.txt): CLI11, which every command's
// translation unit includes and which takes about 3 s to parse, fmt and the standard headers the
// tools use most. Third-party and standard headers only; each file still includes what it uses.
#pragma once

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>
