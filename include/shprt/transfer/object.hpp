// Dynamic objects (issue 37, docs/probes.md "Lighting objects"): a mesh that was not baked with the
// scene, placed in it by a pose and lit from the scene's transfer probes (shade/object_shade.hpp).
//
// Pose convention (docs/conventions.md: world space right-handed, +Y up): the object's vertex p
// (in the mesh file's own frame) is placed at
//
//     world(p) = position + scale · R · (p − pivot),   R = Ry(yaw)·Rx(pitch)·Rz(roll)
//
// with pivot the centre of the mesh's bounding box, so `position` is where the object's centre
// goes; scale is uniform (> 0); yaw/pitch/roll in degrees as the lights' --rotate
// (core/rotation3.hpp: roll about Z first, then pitch about X, then yaw about the up axis Y).
// Normals turn with R (a uniform scale does not change them).
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <string>

namespace shprt {

struct ObjectPose {
    Vec3f position{0, 0, 0};            // world position of the object's pivot
    float scale = 1;                    // uniform, > 0
    Vec3d yaw_pitch_roll_deg{0, 0, 0};  // R = Ry(yaw)·Rx(pitch)·Rz(roll), degrees
};

// Throws Error(invalid_argument) naming the field: a position or angle not finite, a scale not
// finite and > 0.
void check(const ObjectPose& pose);
// R of the pose (exactly the identity when all three angles are 0).
Mat3d object_rotation(const ObjectPose& pose);

// An object as it is lit: its mesh in its own frame, the pivot (its bounding-box centre), and its
// self-shadowing transfer — a shadowed diffuse bake of the mesh alone, one channel, a vector of
// K coefficients per vertex, in the object's frame (bake/object_bake.hpp makes it) — or an empty
// TransferSet: then the object is lit through the clamped cosine about each normal (no
// self-shadowing).
struct DynamicObject {
    Mesh mesh;
    Vec3f pivot{0, 0, 0};
    TransferSet self;  // empty (self.coeffs.empty()) or shade_vertices-shadable for `mesh`
};

}  // namespace shprt
