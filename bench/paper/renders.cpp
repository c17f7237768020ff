// Image stage of the paper study (renders.hpp).
#include "paper/renders.hpp"

#include "paper/image_grid.hpp"

#include "shprt/scene/room.hpp"

#include <fmt/format.h>

namespace shprt::paper {
namespace {

// The shadow edge measured in images (docs/paper_table.md): the back wall's inner top edge
// (z = −kRoomHalfDepth, y = kRoomWallHeight, room.hpp) casts a long straight shadow edge along x
// onto the floor, at z_e = −2.5 − (s.z / s.y)·2.7 for the sun direction s (z_e ≈ −0.64).
// Profiles cross it along z, from lit (z_e + kEdgeLit) to shadowed (z_e − kEdgeDark), on
// kEdgeLines parallel lines x = kEdgeX0 … kEdgeX1, and are averaged: the floor's vertex grid
// (cells of ~13 cm at 20 000 triangles) makes a single line depend on where it falls in a cell.
// That strip of floor is the one stretch of this edge clear of everything else: the chair at
// (1.0, −0.3) ends at x = 1.22, the right wall's shadow begins at x ≈ 1.7 (its penumbra and the
// vertex interpolation reach x ≈ 1.41), the table starts at z = −0.05; the bookshelf's shadow
// (z < −0.76) lies inside the wall's.
constexpr float kEdgeX0 = 1.28f, kEdgeX1 = 1.38f;
// The lit side stops short of the table (z > −0.05); the dark side is longer, so that the
// blurred SH edges reach their dark level inside the profile.
constexpr float kEdgeLit = 0.5f, kEdgeDark = 1.0f;
constexpr int kEdgeLines = 3;
constexpr int kEdgeSamples = 601;  // per line, 2.5 mm apart

}  // namespace

Renders::Renders(const Mesh& mesh, Vec3d s, bool quick, Results& res) : m_mesh(mesh) {
    m_edge_z = -kRoomHalfDepth - static_cast<float>(s.z / s.y) * kRoomWallHeight;
    const float edge_mid_x = 0.5f * (kEdgeX0 + kEdgeX1);
    m_context = std::make_unique<HeadlessGlContext>();
    res.gl_context = m_context->description();
    m_renderer = std::make_unique<Renderer>();
    if (quick) m_edge_size = 160, m_room_w = 160, m_room_h = 90;
    m_edge_target = std::make_unique<RenderTarget>(m_edge_size, m_edge_size);
    m_room_target = std::make_unique<RenderTarget>(m_room_w, m_room_h);
    // Straight down over the middle of the profiles, seeing 1.6 m of floor.
    const float mid_z = m_edge_z + 0.5f * (kEdgeLit - kEdgeDark);
    m_edge_camera.eye = {edge_mid_x, 2.2f, mid_z};
    m_edge_camera.target = {edge_mid_x, 0.0f, mid_z};
    m_edge_camera.up = {0, 0, -1};
    m_edge_camera.fov_y_deg = 40;
    m_edge_camera.near_plane = 0.5f;
    m_edge_camera.far_plane = 5.0f;
    m_room_camera = default_camera(mesh, float(m_room_w) / float(m_room_h));
}

Image Renders::draw(RenderTarget& target, const Camera& camera, ShadeView view) {
    DrawSettings s;
    s.camera = camera;
    s.view = view;
    target.bind();
    m_renderer->draw(s, target.width(), target.height());
    target.resolve();
    return target.read_pixels();
}

// The edge crop (irradiance) and the room (radiance) under one light.
Renders::Pair Renders::render_pair(const TransferSet& t, const ShLight& light, bool scene_changed) {
    Pair r;
    if (scene_changed) m_renderer->set_scene(m_mesh, t);
    m_renderer->set_light(light);
    r.edge = draw(*m_edge_target, m_edge_camera, ShadeView::irradiance);
    r.room = draw(*m_room_target, m_room_camera, ShadeView::radiance);
    return r;
}

Profile Renders::edge_profile(const Image& image) const {
    Profile mean;
    for (int i = 0; i < kEdgeLines; ++i) {
        const float x = kEdgeX0 + (kEdgeX1 - kEdgeX0) * float(i) / float(kEdgeLines - 1);
        const Profile p = image_profile(image, m_edge_camera, {x, 0, m_edge_z + kEdgeLit},
                                        {x, 0, m_edge_z - kEdgeDark}, kEdgeSamples);
        if (i == 0)
            mean = p;
        else
            for (std::size_t k = 0; k < p.value.size(); ++k) mean.value[k] += p.value[k];
    }
    for (double& v : mean.value) v /= kEdgeLines;
    return mean;
}

void Renders::render_row(KRow& row, const TransferSet& t, const TransferSet& ti, const ShLight& sky,
                         const ShLight& sun) {
    const Pair paper_sky = render_pair(t, sky, true);
    const Pair paper_sun = render_pair(t, sun, false);
    const Pair better_sun = render_pair(ti, sun, true);
    row.sun_profile = edge_profile(paper_sun.edge);
    row.sun.edge = measure_edge(row.sun_profile);
    row.sun.has_edge = true;
    row.improved_profile = edge_profile(better_sun.edge);
    row.sun_improved.edge = measure_edge(row.improved_profile);
    row.sun_improved.has_edge = true;
    if (row.paper_size) {
        m_grid_sky.push_back(paper_sky.room);
        m_grid_sun.push_back(paper_sun.room);
        m_grid_better.push_back(better_sun.room);
        m_grid_edge.push_back(paper_sun.edge);
        m_grid_edge_better.push_back(better_sun.edge);
        m_grid_labels.push_back(fmt::format("K={}", row.K));
    }
}

EdgeMeasure Renders::sun_edge(const Mesh& mesh, const TransferSet& t, const ShLight& sun) {
    m_renderer->set_scene(mesh, t);
    m_renderer->set_light(sun);
    return measure_edge(edge_profile(draw(*m_edge_target, m_edge_camera, ShadeView::irradiance)));
}

void Renders::finish(const Truth& truth, Results& res, const std::string& out_dir) {
    // The ground truth's own images, then the grids: rows sky, sun, sun improved (room) and
    // sun, sun improved (edge crops); the truth in the last column.
    const ShLight white = constant_light({1, 1, 1}, 1);
    const TransferSet sky_t = irradiance_as_transfer(truth.sky);
    const TransferSet sun_t = irradiance_as_transfer(truth.sun);
    const Pair truth_sun = render_pair(sun_t, white, true);
    const Pair truth_sky = render_pair(sky_t, white, true);
    res.gt_profile = edge_profile(truth_sun.edge);
    res.gt_edge = measure_edge(res.gt_profile);
    res.gt_has_edge = true;
    m_grid_sky.push_back(truth_sky.room);
    m_grid_sun.push_back(truth_sun.room);
    m_grid_better.push_back(truth_sun.room);
    m_grid_edge.push_back(truth_sun.edge);
    m_grid_edge_better.push_back(truth_sun.edge);
    m_grid_labels.push_back("TRUTH");
    const std::size_t columns = m_grid_labels.size();
    std::vector<Image> room_tiles, edge_tiles;
    std::vector<std::string> room_labels, edge_labels;
    const auto add_row = [&](std::vector<Image>& tiles, std::vector<std::string>& labels,
                             const std::vector<Image>& row, const char* suffix) {
        tiles.insert(tiles.end(), row.begin(), row.end());
        for (const auto& l : m_grid_labels) labels.push_back(l + suffix);
    };
    add_row(room_tiles, room_labels, m_grid_sky, " SKY");
    add_row(room_tiles, room_labels, m_grid_sun, " SUN");
    add_row(room_tiles, room_labels, m_grid_better, " SUN SOBOL");
    add_row(edge_tiles, edge_labels, m_grid_edge, "");
    add_row(edge_tiles, edge_labels, m_grid_edge_better, " SOBOL");
    edge_labels.back() = "TRUTH";
    room_labels.back() = "TRUTH SUN";
    const std::string dir = out_dir + "/";
    const auto save = [&](const std::string& name, const Image& image) {
        save_image(dir + name + ".png", image, 1.0f);
        save_image(dir + name + "_small.png", half_size(image), 1.0f);  // for docs
        res.files.push_back(name + ".png");
        res.files.push_back(name + "_small.png");
    };
    save("grid_room", compose_grid(room_tiles, room_labels, int(columns), 1.3f));
    // Edge crops show irradiance (≈ 2.4 lit): scaled down for the tone map.
    save("grid_edge", compose_grid(edge_tiles, edge_labels, int(columns), 0.3f));
}

}  // namespace shprt::paper
