// A dynamic object lit from the file's transfer probes (docs/probes.md "Lighting objects"):
// `--object MESH --at X,Y,Z [--object-scale S] [--object-rotate YAW,PITCH,ROLL]`, shared by
// `render` and `view`.
#pragma once

#include "shprt/transfer/object.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace shprt::tools {

struct ObjectArgs {
    std::string object, at, rotate;
    double scale = 1;
};

// Adds --object, --at, --object-scale and --object-rotate.
void add_object_options(CLI::App& app, ObjectArgs& args);
// The pose of the parsed options, or none without --object; checked before any file is read
// (one-line Error(invalid_argument): --at missing or not three numbers, a scale ≤ 0, the object
// options without --object).
std::optional<ObjectPose> object_pose_from(const ObjectArgs& args);

}  // namespace shprt::tools
