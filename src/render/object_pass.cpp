#include "object_pass.hpp"

#include "gl_util.hpp"

#include "shprt/core/error.hpp"

#include <epoxy/gl.h>

namespace shprt {

namespace {
// One vertex as uploaded: position, normal, albedo, colour (attributes 0..3), 12 floats.
constexpr std::size_t kFloatsPerVertex = 12;
}  // namespace

ObjectPass::ObjectPass() { glGenVertexArrays(1, &m_vao); }

ObjectPass::~ObjectPass() {
    for (unsigned* b : {&m_vertex_vbo, &m_index_buffer})
        if (*b) glDeleteBuffers(1, b);
    if (m_vao) glDeleteVertexArrays(1, &m_vao);
}

void ObjectPass::set(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                     const ObjectShading& shading) {
    const std::size_t V = shading.positions.size();
    SHPRT_CHECK(
        shading.normals.size() == V && shading.albedo.size() == V && shading.radiance.size() == V,
        invalid_argument, "object shading: arrays of {} vertices disagree", V);
    std::vector<float> vertices(V * kFloatsPerVertex);
    for (std::size_t v = 0; v < V; ++v) {
        float* out = vertices.data() + v * kFloatsPerVertex;
        for (const Vec3f& x :
             {shading.positions[v], shading.normals[v], shading.albedo[v], shading.radiance[v]}) {
            *out++ = x.x;
            *out++ = x.y;
            *out++ = x.z;
        }
    }
    glBindVertexArray(m_vao);
    if (V != m_vertex_count || !m_vertex_vbo) {
        if (m_vertex_vbo) glDeleteBuffers(1, &m_vertex_vbo);
        m_vertex_vbo = gl::make_buffer(GL_ARRAY_BUFFER, vertices.size() * sizeof(float),
                                       vertices.data(), GL_DYNAMIC_DRAW);
        const GLsizei stride = GLsizei(kFloatsPerVertex * sizeof(float));
        for (unsigned a = 0; a < 4; ++a) {
            glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, stride,
                                  reinterpret_cast<const void*>(a * 3 * sizeof(float)));
            glEnableVertexAttribArray(a);
        }
        glDisableVertexAttribArray(4);  // the sun's SH part: 0 (the object has none)
        glDisableVertexAttribArray(5);  // the BRDF entry: 0
        m_vertex_count = V;
    } else {
        glBindBuffer(GL_ARRAY_BUFFER, m_vertex_vbo);
        glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(vertices.size() * sizeof(float)),
                        vertices.data());
    }
    if (triangles != m_triangles || !m_index_buffer) {
        for (const auto& t : triangles)
            for (std::uint32_t i : t)
                SHPRT_CHECK(i < V, invalid_argument, "object triangle index {} (of {} vertices)", i,
                            V);
        if (m_index_buffer) glDeleteBuffers(1, &m_index_buffer);
        m_index_buffer =
            gl::make_buffer(GL_ELEMENT_ARRAY_BUFFER, triangles.size() * sizeof(triangles[0]),
                            triangles.data(), GL_STATIC_DRAW);
        m_triangles = triangles;
        m_index_count = triangles.size() * 3;
    }
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void ObjectPass::draw() const {
    if (m_index_count == 0) return;
    glBindVertexArray(m_vao);
    glDrawElements(GL_TRIANGLES, GLsizei(m_index_count), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

}  // namespace shprt
