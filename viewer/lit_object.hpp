// A probe-lit dynamic object in the viewer (docs/probes.md "Lighting objects"): shaded on the CPU
// (shade_object, shade/object_shade.hpp) and uploaded (Renderer::set_object) again only when its
// pose, the light or the shading it depends on changed since the last frame — the window while
// the user drags it or turns the light, --benchmark with the object moving every frame.
#pragma once

#include "shprt/render/renderer.hpp"
#include "shprt/shade/object_shade.hpp"
#include "shprt/transfer/object.hpp"
#include "shprt/transfer/probes.hpp"

#include <string>
#include <vector>

namespace shprt::viewer {

// What the command line gives: the object (made ready: bake/object_bake.hpp), the file's probes,
// the start pose and the shading choices (k, BRDF, K′: object_shade_options; the eye is each
// frame's camera). No object: `object` null.
struct ViewerObject {
    const DynamicObject* object = nullptr;
    const ProbeGrid* probes = nullptr;
    ObjectPose pose;
    ObjectShadeOptions options;
    std::string label;  // e.g. the file name, for the panel
};

// The object's move in the world for `along` metres to the camera's right, `ahead` metres the way
// it looks and `up` metres along +Y: right and forward are kept horizontal (a camera looking down
// still moves the object over the floor) and normalised, and a direction with no horizontal part
// (looking straight down: forward) moves nothing. The arrow keys, Page Up/Down and G+drag.
Vec3f object_step(Vec3f camera_right, Vec3f camera_forward, float along, float ahead, float up);

// Metres a G+drag moves the object per pixel, at the camera's fly speed (m/s): 400 pixels at
// the default 2 m/s carry it 2 m.
inline constexpr float kObjectDragMetresPerPixelPerSpeed = 0.0025f;

class LitObject {
public:
    explicit LitObject(const ViewerObject& object) : m_object(object) {}
    bool present() const { return m_object.object != nullptr; }
    ObjectPose& pose() { return m_object.pose; }
    const ViewerObject& object() const { return m_object; }

    // Shades and uploads the object when its pose, `light` (the rotated light the scene is
    // shaded with), `options` (the scene's: object_shade_options of its plan) or, for the glossy
    // term (k < 1, radiance), the camera's `eye` changed; returns true when it did. Nothing
    // without an object.
    bool update(Renderer& renderer, const ShLight& light, ObjectShadeOptions options, Vec3f eye);
    // The last shading (positions, colours, whether the pose is outside the grid).
    const ObjectShading& shading() const { return m_shading; }
    double last_shade_ms() const { return m_shade_ms; }

private:
    ViewerObject m_object;
    ObjectShading m_shading;
    bool m_valid = false;
    ObjectPose m_pose;
    ObjectShadeOptions m_options;
    std::vector<float> m_light;
    double m_shade_ms = 0;
};

}  // namespace shprt::viewer
