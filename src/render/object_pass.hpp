// A probe-lit dynamic object drawn with the scene (shade/object_shade.hpp, docs/probes.md
// "Lighting objects"). Private to render/: the Renderer owns one while it has an object
// (Renderer::set_object). The colours are computed on the CPU (shade_object: the reference is
// what is drawn) and uploaded per vertex with the world positions, normals and albedo whenever the
// object or the light moves: 48 bytes a vertex, ~0.5 MB for 10k vertices. It is drawn by the
// scene's own program (its colour plus the sun's direct term, sun_pass.hpp), and it casts into the
// sun's shadow map (draw_triangles).
#pragma once

#include "shprt/scene/mesh.hpp"
#include "shprt/shade/object_shade.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

class ObjectPass {
public:
    ObjectPass();
    ~ObjectPass();
    ObjectPass(const ObjectPass&) = delete;
    ObjectPass& operator=(const ObjectPass&) = delete;

    // Uploads `shading` (its vertex arrays) and, when they differ from the last call's,
    // `triangles`. Throws Error(invalid_argument) when the arrays' sizes disagree or an index is
    // out of range.
    void set(const std::vector<std::array<std::uint32_t, 3>>& triangles,
             const ObjectShading& shading);
    // Draws the triangles with the program in use (the scene's: attributes 0 position, 1 normal,
    // 2 albedo, 3 colour).
    void draw() const;
    // Draws the triangles with positions at attribute 0 only (the sun's depth pass).
    void draw_triangles() const { draw(); }

private:
    unsigned m_vao = 0, m_vertex_vbo = 0, m_index_buffer = 0;
    std::size_t m_vertex_count = 0, m_index_count = 0;
    std::vector<std::array<std::uint32_t, 3>> m_triangles;
};

}  // namespace shprt
