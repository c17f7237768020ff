// Error checks and shader compilation for the OpenGL renderer.
#include "gl_util.hpp"

#include "shprt/core/error.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <string>

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

}  // namespace shprt::gl
