// The test programs' precompiled header (tests/CMakeLists.txt, shprt_test_pch): third-party and
// standard headers only, the ones most test files include, so that a change to shprt's own
// headers never rebuilds it. Each test file still includes what it uses.
#pragma once

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>
