#include "common/object_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/light/light_setup.hpp"

#include <cmath>
#include <vector>

namespace shprt::tools {

void add_object_options(CLI::App& app, ObjectArgs& args) {
    app.add_option("--object", args.object,
                   "A mesh (any scene file) lit from the file's transfer probes (docs/probes.md)");
    app.add_option("--at", args.at, "X,Y,Z: where the object's centre goes (with --object)");
    app.add_option("--object-scale", args.scale, "The object's uniform scale (default 1)");
    app.add_option("--object-rotate", args.rotate,
                   "YAW,PITCH,ROLL in degrees: the object's rotation, as --rotate of lights");
}

std::optional<ObjectPose> object_pose_from(const ObjectArgs& args) {
    if (args.object.empty()) {
        SHPRT_CHECK(args.at.empty() && args.rotate.empty() && args.scale == 1, invalid_argument,
                    "--at, --object-scale and --object-rotate place an object: give --object MESH");
        return std::nullopt;
    }
    SHPRT_CHECK(!args.at.empty(), invalid_argument,
                "--object {}: give its position with --at X,Y,Z", args.object);
    const std::vector<double> at = parse_numbers(args.at, 3, "--at X,Y,Z");
    ObjectPose pose;
    pose.position = {float(at[0]), float(at[1]), float(at[2])};
    SHPRT_CHECK(args.scale > 0 && std::isfinite(args.scale), invalid_argument,
                "--object-scale {}: must be a finite number > 0", args.scale);
    pose.scale = float(args.scale);
    if (!args.rotate.empty()) pose.yaw_pitch_roll_deg = parse_yaw_pitch_roll(args.rotate);
    check(pose);
    return pose;
}

}  // namespace shprt::tools
