// Error checks and shader compilation for the OpenGL renderer.
#include "gl_util.hpp"

#include "shprt/core/error.hpp"
#include "shprt/render/draw_order.hpp"
#include "shprt/render/renderer.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/sh/basis.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace shprt::gl {
namespace {

std::string shader_log(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    return log.c_str();
}

GLuint compile(GLenum stage, const char* source, const char* name) {
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string log = shader_log(shader);
        glDeleteShader(shader);
        fail(ErrorCode::unsupported, "{} {} shader does not compile: {}", name,
             stage == GL_VERTEX_SHADER ? "vertex"
                                       : (stage == GL_COMPUTE_SHADER ? "compute" : "fragment"),
             log);
    }
    return shader;
}

GLuint link(GLuint program, const char* name) {
    glLinkProgram(program);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program, length, nullptr, log.data());
        glDeleteProgram(program);
        fail(ErrorCode::unsupported, "{} program does not link: {}", name, log.c_str());
    }
    return program;
}

}  // namespace

void check(const char* what) {
    const GLenum first = glGetError();
    if (first == GL_NO_ERROR) return;
    while (glGetError() != GL_NO_ERROR) {
    }
    fail(ErrorCode::unsupported, "OpenGL error 0x{:x} in {}", static_cast<unsigned>(first), what);
}

unsigned compile_program(const char* vertex_source, const char* fragment_source, const char* name) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, name);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragment_source, name);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glDeleteShader(vs);  // flagged; freed with the program
    glDeleteShader(fs);
    return link(program, name);
}

unsigned compile_compute_program(const char* source, const char* name) {
    const GLuint cs = compile(GL_COMPUTE_SHADER, source, name);
    const GLuint program = glCreateProgram();
    glAttachShader(program, cs);
    glDeleteShader(cs);
    return link(program, name);
}

unsigned make_buffer(unsigned target, std::size_t bytes, const void* data, unsigned usage) {
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(target, buffer);
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, usage);
    return buffer;
}

void delete_buffer(unsigned& buffer) {
    if (buffer) glDeleteBuffers(1, &buffer);
    buffer = 0;
}

unsigned make_texture_2d(int width, int height, unsigned internal_format) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexStorage2D(GL_TEXTURE_2D, 1, internal_format, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return texture;
}

unsigned upload_draw_orders(const Mesh& mesh, int& lists) {
    const std::size_t list_bytes = mesh.triangles.size() * 3 * sizeof(std::uint32_t);
    const std::vector<std::uint32_t> orders = draw_orders_fit(mesh.triangles.size())
                                                  ? directional_draw_orders(mesh)
                                                  : std::vector<std::uint32_t>{};
    lists = orders.empty() ? 1 : 1 + kDrawOrderCount;
    const unsigned buffer = make_buffer(GL_ELEMENT_ARRAY_BUFFER, list_bytes * std::size_t(lists),
                                        nullptr, GL_STATIC_DRAW);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(list_bytes),
                    mesh.triangles.data());
    if (!orders.empty())
        glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLintptr>(list_bytes),
                        static_cast<GLsizeiptr>(orders.size() * sizeof(std::uint32_t)),
                        orders.data());
    return buffer;
}

const void* draw_order_offset(int lists, std::size_t index_count, const DrawSettings& settings) {
    if (lists == 1 || !settings.front_to_back) return nullptr;
    const int order = draw_order_for(settings.camera.target - settings.camera.eye);
    return reinterpret_cast<const void*>(std::size_t(1 + order) * index_count *
                                         sizeof(std::uint32_t));
}

// The constants of sh_eval_k's recurrence (sh/basis.hpp) for every (l, m ≥ 0), l < bands, at
// flat index l(l+1)+m, two floats each, in the layout the shading shader reads (see there).
std::vector<float> recurrence_table(int bands) {
    std::vector<float> t(std::size_t(2) * sh_count(bands), 0.0f);
    for (int m = 0; m < bands; ++m)
        for (int l = m; l < bands; ++l) {
            const std::size_t i = 2 * std::size_t(sh_index(l, m));
            if (l == m) {
                t[i] = m > 0 ? static_cast<float>(-std::sqrt((2.0 * m + 1) / (2.0 * m))) : 1.0f;
            } else {
                const double ll = l, mm = m;
                t[i] = static_cast<float>(std::sqrt((4 * ll * ll - 1) / (ll * ll - mm * mm)));
                t[i + 1] = static_cast<float>(
                    std::sqrt(((ll - 1) * (ll - 1) - mm * mm) / (4 * (ll - 1) * (ll - 1) - 1)));
            }
        }
    return t;
}

}  // namespace shprt::gl
