// Image stage of the paper study: renders with the shared OpenGL renderer (headless EGL) — the room
// under each light, and a top-down crop of the floor at the back wall's shadow edge — the edge
// width measured on those crops (measure_edge, paper_metrics.hpp), and the image grids that set
// each basis size beside the ground truth.
#pragma once

#include "paper/ground_truth.hpp"
#include "paper/paper_metrics.hpp"
#include "paper/paper_study.hpp"

#include "shprt/light/image.hpp"
#include "shprt/light/light.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/transfer/transfer.hpp"

#include <memory>
#include <string>
#include <vector>

namespace shprt::paper {

class Renders {
public:
    // Opens a headless OpenGL context (its description goes to results.gl_context as soon as it
    // exists), the renderer and the render targets (smaller with `quick`), and places the cameras:
    // the room's default view, and straight down over the shadow edge that the sun in direction
    // `sun_dir` draws on the floor. Throws Error when OpenGL does not work here.
    Renders(const Mesh& mesh, Vec3d sun_dir, bool quick, Results& results);

    // Renders row.K: the room under `sky` and `sun` with the paper's bake and under `sun` with the
    // improved one, with the edge crops; measures the edge (row.sun.edge, row.sun_improved.edge,
    // with their profiles). A row of the paper's sizes keeps its images for the grids. Throws Error
    // when the driver refuses (a transfer buffer too large, say): the row is then left unchanged.
    void render_row(KRow& row, const TransferSet& paper, const TransferSet& improved,
                    const ShLight& sky, const ShLight& sun);

    // The edge of render_row's crop for any mesh of the room (a refined or texel bake, another
    // tessellation) with its transfer under `sun`: the same camera, profiles and measure_edge.
    // Leaves that scene set: the next render_row sets its own.
    EdgeMeasure sun_edge(const Mesh& mesh, const TransferSet& transfer, const ShLight& sun);

    // Renders the ground truth the same way (irradiance_as_transfer under a white light) and
    // measures its edge (results.gt_profile, gt_edge, gt_has_edge); then writes grid_room.png and
    // grid_edge.png with half-size copies (_small) into out_dir and appends them to results.files.
    void finish(const Truth& truth, Results& results, const std::string& out_dir);

private:
    struct Pair {
        Image edge, room;
    };
    Image draw(RenderTarget& target, const Camera& camera, ShadeView view);
    Pair render_pair(const TransferSet& t, const ShLight& light, bool scene_changed);
    Profile edge_profile(const Image& image) const;

    const Mesh& m_mesh;
    float m_edge_z = 0;  // where the back wall's shadow edge crosses the profiles
    std::unique_ptr<HeadlessGlContext> m_context;
    std::unique_ptr<Renderer> m_renderer;
    std::unique_ptr<RenderTarget> m_edge_target, m_room_target;
    Camera m_edge_camera, m_room_camera;
    int m_edge_size = 400, m_room_w = 320, m_room_h = 180;
    // Grid rows, one tile per paper size: sky, sun, sun improved (room) and sun, sun improved
    // (edge crops); the truth is added as the last column.
    std::vector<Image> m_grid_sky, m_grid_sun, m_grid_better, m_grid_edge, m_grid_edge_better;
    std::vector<std::string> m_grid_labels;
};

}  // namespace shprt::paper
