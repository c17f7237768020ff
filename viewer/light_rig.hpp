// The viewer's light: a source (light specs + window, projected once with full bands) and a
// rotation that the user changes by dragging with a modifier key. Rotating is done on the SH
// coefficients (rotate_light, ShRotation), never by re-projecting the source, so a drag costs
// O(bands³) per channel whatever the map's resolution, and the light stays exactly band-limited.
//
// Composition. The rotation applied to the source is R = D · B, where B is the base rotation of
// the command line (--rotate YAW,PITCH,ROLL: B = Ry(yaw)·Rx(pitch)·Rz(roll), as prepare_light
// applies it) and D the accumulated drags: each drag d pre-multiplies, D ← R_d · D, so it turns the
// light as it currently appears, about world axes. The source and the turned light come from the
// one light path (light/light_setup.hpp: light_source, rotated_light), so with no drag the light
// equals prepare_light(setup, K) bit for bit.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"

#include <optional>

namespace shprt::viewer {

// Radians of light rotation per pixel of drag.
inline constexpr double kLightRadiansPerPixel = 0.01;

// The rotation of one drag of (dx, dy) pixels (x right, y down): a yaw about world +Y by
// dx·kLightRadiansPerPixel, then a pitch about the unit world vector `right` (the camera's
// right axis) by dy·kLightRadiansPerPixel:  R_d = Rot(right, dy·rate) · Ry(dx·rate).
// So dragging right turns the light around the vertical axis (a sun keeps its elevation), and
// dragging down tips it about the horizontal screen axis. `right` need not be unit (it is
// normalised); a zero `right` skips the pitch.
Mat3d light_drag_rotation(double dx_px, double dy_px, Vec3d right);

class LightRig {
public:
    // A rig for lights of basis size K (1..kMaxLightK); starts with no source (has_source()
    // false).
    explicit LightRig(int K);

    // The source becomes light_source(setup, K) (the specs projected with full bands,
    // sh_count(sh_bands_for(K)) coefficients, windowed) and the base rotation B
    // light_rotation(setup). The accumulated drag D is kept. Throws the errors of make_light
    // (naming the spec or file) and leaves the rig unchanged when it does.
    void set_source(const LightSetup& setup);
    bool has_source() const { return m_has_source; }
    const LightSetup& setup() const { return m_setup; }

    // D ← light_drag_rotation(dx, dy, right) · D.
    void drag(double dx_px, double dy_px, Vec3d right);
    // D ← identity.
    void reset_drag();
    const Mat3d& drag_rotation() const { return m_drag; }
    // R = D · B.
    Mat3d rotation() const;

    // The light: rotated_light(source(), rotation(), K), the full-band source rotated, then
    // truncated to the first K coefficients (3·K floats, channel-major). Needs a source
    // (Error(invalid_argument)).
    ShLight light() const;
    // The full-band source, windowed, not rotated (sh_count(sh_bands_for(K)) coefficients): with
    // rotation(), what Renderer::set_light takes so that it turns the background without
    // rebuilding it. Needs a source.
    const ShLight& source() const;
    // The setup's sun kept out of the SH sum (--sun) in the source's frame — prepare_sun without
    // the base rotation, which Renderer::set_light applies to it with rotation() — or nullptr.
    const PreparedSun* sun() const { return m_sun ? &*m_sun : nullptr; }
    int K() const { return m_K; }

private:
    int m_K;
    bool m_has_source = false;
    LightSetup m_setup;
    ShLight m_source;  // full bands, windowed, not rotated
    std::optional<PreparedSun> m_sun;
    Mat3d m_base = Mat3d::identity();
    Mat3d m_drag = Mat3d::identity();
};

}  // namespace shprt::viewer
