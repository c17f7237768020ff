// The interactive viewer's window and frame loop (viewer_app.hpp). Display of precomputed
// radiance transfer as in Sloan, Kautz & Snyder 2002 (per-vertex SH dot products on the GPU,
// light rotated in SH), through the shared Renderer.
#include "viewer_app.hpp"

#include "camera_controller.hpp"
#include "glfw_session.hpp"
#include "light_rig.hpp"
#include "panel.hpp"

#include "shprt/bake/background.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/gpu_gl_interop.hpp"
#include "shprt/config.hpp"
#include "shprt/core/error.hpp"
#include "shprt/render/gl_context.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <utility>

namespace shprt::viewer {
namespace {

using Clock = std::chrono::steady_clock;

// ImGui for the lifetime of the object (after the window, before the renderer's GL objects die).
class ImGuiLayer {
public:
    explicit ImGuiLayer(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;  // no imgui.ini written into the working directory
        const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
        std::error_code ec;
        if (std::filesystem::exists(font, ec)) io.Fonts->AddFontFromFileTTF(font, 15.0f);
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to our callbacks
        ImGui_ImplOpenGL3_Init("#version 430 core");
    }
    ~ImGuiLayer() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;
};

// The window; it collects mouse-wheel steps (GLFW reports them only through a callback, which
// is installed before ImGui's so that ImGui chains to it).
class Window {
public:
    Window(int width, int height, const std::string& title)
        : m_window(create_gl_window(width, height, title, true)) {
        glfwSetWindowUserPointer(m_window, this);
        glfwSetScrollCallback(m_window, [](GLFWwindow* window, double, double dy) {
            if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
            static_cast<Window*>(glfwGetWindowUserPointer(window))->m_scroll += dy;
        });
    }
    ~Window() { glfwDestroyWindow(m_window); }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
    GLFWwindow* get() const { return m_window; }
    // Wheel steps since the last call.
    double take_scroll() { return std::exchange(m_scroll, 0.0); }

private:
    GLFWwindow* m_window;
    double m_scroll = 0;
};

// The keys the loop reacts to once per press.
struct KeyEdges {
    bool tab = false, r = false;
};

class App {
public:
    App(const Mesh& mesh, const TransferSet& transfer, const WindowOptions& options,
        const std::optional<BakeOptions>& bake);
    ~App();
    WindowReport run();

private:
    void init_state();
    void set_light_source();
    void apply_panel();
    void handle_input(float seconds);
    void update_bake();
    void start_bake(const BakeOptions& options);
    void show_transfer();
    const TransferSet& shown_transfer() const {
        return m_panel.params.direct ? m_direct : m_transfer;
    }
    DrawSettings draw_settings();
    void update_object(const DrawSettings& settings);

    const Mesh& m_mesh;
    const TransferSet& m_transfer;
    TransferSet m_direct;  // its direct part (interreflected transfer only; else empty)
    WindowOptions m_options;
    GlfwSession m_glfw;
    Window m_window;
    ImGuiLayer m_imgui;
    Renderer m_renderer;
    FrameTarget m_target;
    CameraController m_camera;
    Camera m_start_camera;
    LightRig m_light;
    LitObject m_object;
    PanelState m_panel;
    PanelShading m_shading;  // m_panel.params resolved against the transfer shown
    // Declared before the bake: the bake (which may write into the mapped buffer) ends first.
    std::unique_ptr<GlBufferInterop> m_interop;
    std::unique_ptr<BackgroundBake> m_bake;
    bool m_bake_reported = false;
    int m_frames_ready = 0;  // frames drawn with nothing left to bake
    bool m_reshade_once = false;
    WindowReport m_report;

    double m_last_x = 0, m_last_y = 0;
    bool m_have_cursor = false;
    KeyEdges m_keys_down;
};

App::App(const Mesh& mesh, const TransferSet& transfer, const WindowOptions& options,
         const std::optional<BakeOptions>& bake)
    : m_mesh(mesh),
      m_transfer(transfer),
      m_options(options),
      m_window(options.frame.width, options.frame.height, options.title),
      m_imgui(m_window.get()),
      m_camera(options.frame.draw.camera, mesh_bounds(mesh)),
      m_start_camera(options.frame.draw.camera),
      m_light(std::min(transfer.layout.K, kMaxLightK)),
      m_object(options.object) {
    glfwSwapInterval(options.vsync ? 1 : 0);
    if (!transfer.direct.empty()) m_direct = transfer.direct_only();
    m_panel.params = options.params;
    m_panel.has_direct = !m_direct.coeffs.empty();
    m_panel.params.direct = m_panel.has_direct && options.params.direct;
    m_light.set_source(options.light);  // errors (a missing file) end the program: one line
    show_transfer();
    m_report.context = gl_context_summary();
    init_state();
    if (bake) start_bake(*bake);
}

App::~App() {
    // The worker may still write into the mapped buffer: stop it before anything else goes.
    if (m_bake) {
        m_bake->cancel();
        m_bake->wait();
    }
    if (m_interop) m_interop->unmap();
}

// Uploads the transfer the panel asks for (the whole, or an interreflected bake's direct part).
void App::show_transfer() {
    m_renderer.set_shadow_map_size(choose_shadow_map_size(true));
    m_renderer.set_sun_filter(choose_sun_filter(true));
    m_renderer.set_moving_shadow_map_size(choose_moving_shadow_map_size(true));
    m_renderer.set_sun(m_light.sun());
    m_renderer.set_scene(m_mesh, shown_transfer());
    m_renderer.set_light(m_light.source(), m_light.rotation());
}

void App::init_state() {
    PanelState& s = m_panel;
    s.scene_label =
        fmt::format("{}: {} vertices, {} triangles, K={}", m_options.scene_label,
                    m_mesh.vertex_count(), m_mesh.triangle_count(), m_renderer.scene_K());
    s.gl_label = m_report.context;
    s.K_file = m_renderer.scene_K();
    s.K_max = m_renderer.effective_K(0);
    ShadingParams& p = s.params;  // the command line's (the constructor)
    p.coeffs = p.coeffs > 0 ? std::min(p.coeffs, s.K_max) : s.K_max;
    // Diffuse texels, and vector transfer under a sun kept out of the SH sum (the paper's glossy
    // term is not linear in the light: Renderer::set_sun), are drawn with k = 1.
    s.diffuse_only =
        !is_matrix(m_transfer.layout) && (is_texel(m_transfer.layout) || m_light.sun());
    if (s.diffuse_only) p.k = 1;
    // The paper's term (a file turned into vectors before the window): its Phong exponent is
    // the gloss slider's.
    if (p.glossy == GlossyTerm::paper && p.brdf) p.gloss = std::exchange(p.brdf, {})->parameter;
    s.matrices = m_renderer.scene_has_matrices();
    s.has_material_brdfs = m_renderer.scene_has_material_brdfs();
    s.material_label = describe_brdfs(m_mesh);
    if (p.albedo) s.albedo_colour = *p.albedo;
    s.transfer_label = describe_gpu_transfer(m_transfer, m_renderer.transfer_bytes_per_vertex());
    if (const PreparedSun* sun = m_light.sun())
        s.sun_label = fmt::format("sun: {:g}° kept out of the SH sum, a {}² shadow map; {}",
                                  sun->sun.radius_deg, m_renderer.shadow_map_size(),
                                  m_renderer.sun_bounced() ? "bounced light from T - T0"
                                                           : "direct only (no direct part in "
                                                             "the file: not interreflected)");
    s.wireframe = m_options.frame.draw.wireframe;
    s.background = m_options.frame.draw.background;
    s.choices = light_choices(m_options.light.specs);
    // The command line's light is selected: its own entry, the sum, or builtin by default.
    const auto& specs = m_options.light.specs;
    if (specs.empty() || (specs.size() == 1 && specs[0] == "builtin"))
        s.choice = 0;
    else
        s.choice = static_cast<int>(s.choices.size()) - 1;
    s.window = static_cast<int>(m_options.light.window);
    s.window_strength = static_cast<float>(m_options.light.window_strength);
    s.fly_speed = m_camera.speed();
    s.vsync = m_options.vsync;
    s.msaa = choose_samples(m_options.frame.msaa, true);
    s.has_object = m_object.present();
    if (s.has_object) {
        const ViewerObject& o = m_object.object();
        s.object_label = fmt::format(
            "{}: {} vertices, {}", o.label, o.object->mesh.vertex_count(),
            o.object->self.coeffs.empty() ? "no self-shadowing" : "self-shadowing baked");
        for (int a = 0; a < 3; ++a) s.object_position[a] = o.pose.position[a];
    }
}

void App::set_light_source() {
    LightSetup setup = m_options.light;  // keeps --rotate as the base rotation
    if (m_panel.choice >= 0 && m_panel.choice < static_cast<int>(m_panel.choices.size()))
        setup.specs = m_panel.choices[static_cast<std::size_t>(m_panel.choice)].specs;
    else
        setup.specs = {m_panel.typed_spec};
    setup.window = static_cast<WindowKind>(m_panel.window);
    setup.window_strength = m_panel.window_strength;
    try {
        m_light.set_source(setup);
        m_renderer.set_sun(m_light.sun());
        m_renderer.set_light(m_light.source(), m_light.rotation());
        m_panel.light_error.clear();
    } catch (const Error& e) {
        // A bad spec or a missing file typed in the panel: say so and keep the old light.
        m_panel.light_error = e.what();
    }
}

void App::apply_panel() {
    if (m_panel.direct_changed) {
        show_transfer();
        m_reshade_once = true;
    }
    if (m_panel.light_source_changed) set_light_source();
    if (m_panel.reset_light_rotation) {
        m_light.reset_drag();
        m_renderer.set_light(m_light.source(), m_light.rotation());
    }
    if (m_panel.reset_camera) {
        const CameraMode mode = m_camera.mode();
        m_camera = CameraController(m_start_camera, mesh_bounds(m_mesh));
        m_camera.set_mode(mode);
        m_panel.fly_speed = m_camera.speed();
    }
    if (m_panel.camera_mode_changed)
        m_camera.set_mode(m_panel.camera_mode == 1 ? CameraMode::fly : CameraMode::orbit);
    m_camera.set_speed(m_panel.fly_speed);
    glfwSwapInterval(m_panel.vsync ? 1 : 0);
}

void App::handle_input(float seconds) {
    GLFWwindow* w = m_window.get();
    const ImGuiIO& io = ImGui::GetIO();
    double x = 0, y = 0;
    glfwGetCursorPos(w, &x, &y);
    const double dx = m_have_cursor ? x - m_last_x : 0, dy = m_have_cursor ? y - m_last_y : 0;
    m_last_x = x;
    m_last_y = y;
    m_have_cursor = true;

    if (!io.WantCaptureMouse) {
        const bool left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
        const bool right = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                           glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
        const bool modifier = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                              glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS ||
                              glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
                              glfwGetKey(w, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
        // G held ("grab", as in Blender; Alt+drag belongs to many window managers) and a drag
        // carry the object: the left button over the floor (right and away as the cursor goes
        // right and up), the right button up and down.
        const bool grab = !io.WantCaptureKeyboard && glfwGetKey(w, GLFW_KEY_G) == GLFW_PRESS;
        if (grab && m_object.present() && (left || right)) {
            const float metres = kObjectDragMetresPerPixelPerSpeed * m_camera.speed();
            const Vec3f step =
                left ? object_step(m_camera.right(), m_camera.forward(), float(dx) * metres,
                                   float(-dy) * metres, 0)
                     : object_step(m_camera.right(), m_camera.forward(), 0, 0, float(-dy) * metres);
            for (int a = 0; a < 3; ++a) m_panel.object_position[a] += step[a];
        } else if (left && modifier && (dx != 0 || dy != 0)) {
            m_light.drag(dx, dy, cast<double>(m_camera.right()));
            m_renderer.set_light(m_light.source(), m_light.rotation());
        } else if (left) {
            m_camera.rotate(static_cast<float>(dx), static_cast<float>(dy));
        } else if (right) {
            int fw = 0, fh = 0;
            glfwGetWindowSize(w, &fw, &fh);
            m_camera.pan(static_cast<float>(dx), static_cast<float>(dy), static_cast<float>(fh));
        }
    }
    const double scroll = m_window.take_scroll();
    if (scroll != 0) m_camera.zoom(static_cast<float>(scroll));

    if (io.WantCaptureKeyboard) return;
    auto down = [w](int key) { return glfwGetKey(w, key) == GLFW_PRESS; };
    if (m_object.present()) {
        // The object: arrows along the camera's right and forward (kept horizontal), Page Up and
        // Down along +Y, at half the fly speed.
        const float metres = 0.5f * m_camera.speed() * seconds;
        const auto axis = [&](int plus, int minus) {
            return float(int(down(plus)) - int(down(minus))) * metres;
        };
        const Vec3f step = object_step(
            m_camera.right(), m_camera.forward(), axis(GLFW_KEY_RIGHT, GLFW_KEY_LEFT),
            axis(GLFW_KEY_UP, GLFW_KEY_DOWN), axis(GLFW_KEY_PAGE_UP, GLFW_KEY_PAGE_DOWN));
        for (int a = 0; a < 3; ++a) m_panel.object_position[a] += step[a];
    }
    Vec3f motion{0, 0, 0};
    if (down(GLFW_KEY_W)) motion.z += 1;
    if (down(GLFW_KEY_S)) motion.z -= 1;
    if (down(GLFW_KEY_D)) motion.x += 1;
    if (down(GLFW_KEY_A)) motion.x -= 1;
    if (down(GLFW_KEY_E)) motion.y += 1;
    if (down(GLFW_KEY_Q)) motion.y -= 1;
    if (!(motion == Vec3f{0, 0, 0})) m_camera.move(motion, seconds);
    const bool tab = down(GLFW_KEY_TAB), r = down(GLFW_KEY_R);
    if (tab && !m_keys_down.tab) {
        m_camera.set_mode(m_camera.mode() == CameraMode::orbit ? CameraMode::fly
                                                               : CameraMode::orbit);
        m_panel.camera_mode = m_camera.mode() == CameraMode::fly ? 1 : 0;
    }
    if (r && !m_keys_down.r) m_panel.reset_camera = true;  // applied next frame
    m_keys_down = {tab, r};
    if (down(GLFW_KEY_ESCAPE)) glfwSetWindowShouldClose(w, GLFW_TRUE);
}

void App::start_bake(const BakeOptions& options) {
    Device device = resolve_device(options.device, options.device_index);
    // The error-bounded bake runs on the CPU; `auto` takes it there, as bake() does.
    if (options.target_error > 0 && options.device == Device::automatic) device = Device::cpu;
    float* device_output = nullptr;
    std::size_t device_bytes = 0;
    std::string interop_note;
    // A local direction set's rows are rotated to world space on the host (docs/sampling.md), so
    // its GPU bake cannot write into the GL buffer: its chunks come through the host.
    const bool local = options.direction_frame == DirectionFrame::local;
    if (SHPRT_HAS_CUDA && device == Device::cuda && local)
        interop_note = " (local directions: chunks via the host)";
    if (SHPRT_HAS_CUDA && device == Device::cuda && !local) {
        // The GPU bake writes straight into the shader storage buffer: no host round trip. The
        // buffer stays mapped (and is not drawn) until the bake ends.
        try {
            m_interop = std::make_unique<GlBufferInterop>(m_renderer.transfer_buffer());
            device_output = m_interop->map(device_bytes);
        } catch (const Error& e) {
            // E.g. the window's OpenGL runs on another device (llvmpipe under Xvfb): the GPU
            // bake still runs, and its chunks come through the host like a CPU bake's.
            m_interop.reset();
            device_output = nullptr;
            interop_note =
                fmt::format(" (no CUDA-OpenGL interop: {}; chunks via the host)", e.what());
        }
    }
    BakeOptions o = options;
    o.device = device;
    // The device sink checks at the bake's start that the mapped buffer holds every row.
    std::unique_ptr<TransferSink> device_sink;
    if (device_output)
        device_sink = std::make_unique<DeviceSink>(device_output, device_bytes / sizeof(float));
    m_bake = std::make_unique<BackgroundBake>(m_mesh, o, std::move(device_sink));
    m_panel.baking = true;
    m_panel.bake_status =
        o.target_error > 0
            ? fmt::format("refining K={} toward error {:g} on {} (S up to {})", o.K, o.target_error,
                          to_string(device), bake_set_size(o))
            : fmt::format("baking K={}, S={} on {}{}{}", o.K, o.samples, to_string(device),
                          device_output ? " into the GL buffer (CUDA interop)" : "", interop_note);
}

// An error-bounded bake's rounds (RefineRound), for the panel: the estimate falling as it runs.
std::string refine_text(const RefineRound& r, double target) {
    if (r.round == 0) return fmt::format("refining toward error {:g}: first round", target);
    return fmt::format(
        "round {} of {} (S up to {}): estimated error worst {:.4f}, 99th percentile {:.4f}; {:.1f} "
        "% "
        "of receivers over {:g}; mean S {:.0f}",
        r.round, r.rounds, r.max_samples, r.worst, r.p99, 100 * r.over_target, target,
        r.mean_samples);
}

void App::update_bake() {
    if (!m_bake) return;
    // CPU bakes: every finished chunk goes into the buffer now (the GL thread owns the context).
    for (const TransferChunk& chunk : m_bake->chunks().take_all())
        m_renderer.update_transfer(chunk.first, chunk.count, chunk.rows.data());
    m_panel.bake_fraction = static_cast<float>(m_bake->fraction_done());
    const double target = m_bake->options().target_error;
    if (target > 0 && !m_bake->done())
        m_panel.bake_status = refine_text(m_bake->refine_round(), target);
    if (!m_bake->done() || m_bake_reported) return;
    m_bake->wait();
    if (m_interop) {
        m_interop->unmap();  // CUDA's writes become visible to OpenGL
        // The renderer did not see these writes (they bypassed update_transfer): make the next
        // draw recompute its cached per-vertex colours.
        m_reshade_once = true;
    }
    m_bake_reported = true;
    m_panel.baking = false;
    m_report.bake_seconds = m_bake->seconds();
    switch (m_bake->state()) {
        case BakeState::finished:
            m_report.bake_finished = true;
            m_panel.bake_status = fmt::format("baked in {:.2f} s ({})", m_bake->seconds(),
                                              m_bake->result().stats.device_name);
            if (target > 0)
                m_panel.bake_status += "; " + refine_text(m_bake->refine_round(), target);
            break;
        case BakeState::cancelled:
            m_panel.bake_status = "bake cancelled";
            break;
        default:
            m_report.bake_error = m_bake->error();
            m_panel.bake_status = "bake failed: " + m_report.bake_error;
            break;
    }
}

// The panel's shading resolved as the command line's (PanelShading), with the window's camera
// and display choices.
DrawSettings App::draw_settings() {
    m_shading.update(m_panel.params, m_mesh, shown_transfer(), m_options.scene_label);
    m_panel.shading_error = m_shading.error();
    DrawSettings s = m_shading.settings();
    s.camera = m_camera.camera();
    s.wireframe = m_panel.wireframe;
    s.background = m_panel.background;
    s.clear_color = m_options.frame.draw.clear_color;
    s.front_to_back = m_options.frame.draw.front_to_back;
    return s;
}

// The object at the panel's position, shaded again when it or the light moved.
void App::update_object(const DrawSettings& settings) {
    if (!m_object.present()) return;
    ObjectPose& pose = m_object.pose();
    pose.position = {m_panel.object_position[0], m_panel.object_position[1],
                     m_panel.object_position[2]};
    if (!m_object.update(m_renderer, m_light.light(),
                         object_shade_options(m_shading.plan(), settings.view),
                         settings.camera.eye))
        return;
    const ObjectShading& lit = m_object.shading();
    m_panel.object_status =
        fmt::format("shaded in {:.1f} ms (K'={}){}", m_object.last_shade_ms(), lit.K_used,
                    lit.clamped ? "; outside the probe grid: lit from its edge" : "");
}

WindowReport App::run() {
    GLFWwindow* w = m_window.get();
    const auto start = Clock::now();
    auto last = start;
    while (!glfwWindowShouldClose(w)) {
        glfwPollEvents();
        const auto now = Clock::now();
        const float dt = std::chrono::duration<float>(now - last).count();
        last = now;
        if (m_report.frames > 0) {
            // Smoothed over ~20 frames so the numbers can be read.
            const float ms = 1e3f * dt;
            m_panel.frame_ms = m_panel.frame_ms > 0 ? 0.95f * m_panel.frame_ms + 0.05f * ms : ms;
            m_panel.fps = m_panel.frame_ms > 0 ? 1e3f / m_panel.frame_ms : 0;
        }
        update_bake();

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        if (m_options.show_panel) draw_panel(m_panel);
        apply_panel();
        handle_input(dt);

        int width = 0, height = 0;
        glfwGetFramebufferSize(w, &width, &height);
        ImGui::Render();
        if (width > 0 && height > 0) {
            m_target.prepare(width, height, m_panel.msaa, 0);
            m_panel.msaa_samples = m_target.samples();
            const bool buffer_mapped = m_interop && m_interop->mapped();
            if (!buffer_mapped) {
                DrawSettings settings = draw_settings();
                settings.reshade = std::exchange(m_reshade_once, false);
                update_object(settings);
                draw_frame(m_renderer, m_target, settings,
                           static_cast<float>(m_shading.params().exposure), 0, width, height);
            } else {
                // The GPU bake owns the transfer buffer until it ends: show the panel only.
                glBindFramebuffer(GL_FRAMEBUFFER, 0);
                glViewport(0, 0, width, height);
                glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
                glClear(GL_COLOR_BUFFER_BIT);
            }
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glViewport(0, 0, width, height);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        }
        ++m_report.frames;
        // With a bake, max_frames counts from the bake's end, so that the last frame shows it.
        if (!m_bake || m_bake_reported) ++m_frames_ready;
        const bool last_frame = m_options.max_frames > 0 && m_frames_ready >= m_options.max_frames;
        if (last_frame && !m_options.window_screenshot.empty() && width > 0 && height > 0)
            save_png(m_options.window_screenshot, read_framebuffer(0, width, height));
        glfwSwapBuffers(w);
        if (last_frame) break;
    }
    m_report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return m_report;
}

}  // namespace

WindowReport run_window(const Mesh& mesh, const TransferSet& transfer, const WindowOptions& options,
                        const std::optional<BakeOptions>& bake) {
    App app(mesh, transfer, options, bake);
    return app.run();
}

}  // namespace shprt::viewer
