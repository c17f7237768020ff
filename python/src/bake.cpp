// shprt.bake (bake/bake.hpp): the GIL is released while the library bakes; the library calls
// BakeOptions::progress only from the thread that called bake() (src/bake/progress.hpp), which
// is the Python thread that called shprt.bake, so the callback takes the GIL back there and runs
// the Python function. No worker thread ever touches Python.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/bake/bake.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <exception>
#include <limits>
#include <optional>

namespace shprt::python {

using namespace pybind11::literals;

namespace {

BakeOptions bake_options(std::optional<int> bands, std::optional<int> coeffs, std::int64_t samples,
                         const std::string& sampler, const std::string& transfer,
                         std::uint64_t seed, int threads, const std::string& device,
                         const py::object& bounces, double tolerance, bool two_sided,
                         std::int64_t indirect_samples, const py::object& source_spacing) {
    BakeOptions o;
    SHPRT_CHECK(!(bands && coeffs), invalid_argument,
                "bands and coeffs both given; use one (K = bands²)");
    if (bands) {
        SHPRT_CHECK(*bands >= 1 && *bands <= kMaxComputeBands, invalid_argument,
                    "bands={}: must be 1 to {} (K = bands², at most {})", *bands, kMaxComputeBands,
                    kMaxBakeCoeffs);
        o.K = sh_count(*bands);
    } else if (coeffs) {
        o.K = *coeffs;
    }
    SHPRT_CHECK(samples >= 1 && samples <= std::int64_t(kMaxBakeSamples), invalid_argument,
                "samples={}: must be 1 to {}", samples, kMaxBakeSamples);
    o.samples = std::uint32_t(samples);
    o.sampler = parse_sampler_kind(sampler);
    o.transfer = parse_transfer_kind(transfer);
    o.seed = seed;
    o.threads = threads;
    o.device = parse_device(device);
    // Interreflected transfer: bounces N ≥ 0 or 'converged' (until the largest relative change is
    // under `tolerance`), as `shprt bake --bounces`.
    if (py::isinstance<py::str>(bounces)) {
        const std::string name = bounces.cast<std::string>();
        SHPRT_CHECK(name == "converged", invalid_argument,
                    "bounces='{}': expected a number of bounces or 'converged'", name);
        o.converge = true;
    } else {
        SHPRT_CHECK(py::isinstance<py::int_>(bounces) && !py::isinstance<py::bool_>(bounces),
                    invalid_argument, "bounces: expected an int or 'converged', got {}",
                    py::str(py::type::of(bounces).attr("__name__")).cast<std::string>());
        const auto n = bounces.cast<long long>();
        SHPRT_CHECK(n >= 0 && n <= o.max_bounces, invalid_argument, "bounces={}: must be 0 to {}",
                    n, o.max_bounces);
        o.bounces = int(n);
    }
    o.tolerance = tolerance;
    o.two_sided = two_sided;
    // As `shprt bake --indirect-samples` and `--source-spacing` (a number of metres or
    // 'vertices'); 0 / None = the defaults.
    SHPRT_CHECK(indirect_samples >= 0 && indirect_samples <= std::int64_t(kMaxBakeSamples),
                invalid_argument, "indirect_samples={}: must be 0 (default) to {}",
                indirect_samples, kMaxBakeSamples);
    o.indirect_samples = std::uint32_t(indirect_samples);
    if (py::isinstance<py::str>(source_spacing)) {
        const std::string name = source_spacing.cast<std::string>();
        SHPRT_CHECK(name == "vertices", invalid_argument,
                    "source_spacing='{}': expected metres (> 0) or 'vertices'", name);
        o.source_spacing = std::numeric_limits<float>::infinity();
    } else if (!source_spacing.is_none()) {
        const double metres = source_spacing.cast<double>();
        SHPRT_CHECK(metres > 0 && std::isfinite(metres), invalid_argument,
                    "source_spacing={}: expected metres (> 0) or 'vertices'", metres);
        o.source_spacing = float(metres);
    }
    SHPRT_CHECK(o.transfer == TransferKind::interreflected ||
                    (indirect_samples == 0 && source_spacing.is_none()),
                invalid_argument,
                "indirect_samples and source_spacing need transfer='interreflected'");
    validate(o);
    return o;
}

py::array bake_py(py::handle vertices, py::handle faces, py::handle normals, py::handle albedo,
                  std::optional<int> bands, std::optional<int> coeffs, std::int64_t samples,
                  const std::string& sampler, const std::string& transfer, std::uint64_t seed,
                  const py::object& bounces, double tolerance, bool two_sided,
                  std::int64_t indirect_samples, const py::object& source_spacing, int threads,
                  const std::string& device, py::object progress) {
    BakeOptions options =
        bake_options(bands, coeffs, samples, sampler, transfer, seed, threads, device, bounces,
                     tolerance, two_sided, indirect_samples, source_spacing);
    // A shprt.Mesh is used in place; arrays become a Mesh (one copy, checked).
    std::optional<Mesh> own;
    const Mesh* mesh = nullptr;
    if (py::isinstance<Mesh>(vertices)) {
        SHPRT_CHECK(faces.is_none() && normals.is_none() && albedo.is_none(), invalid_argument,
                    "bake(mesh): faces, normals and albedo come from the shprt.Mesh; pass none");
        mesh = &vertices.cast<const Mesh&>();
    } else {
        SHPRT_CHECK(!faces.is_none(), invalid_argument,
                    "bake(vertices, faces): faces (T, 3) is required with a vertex array");
        own = mesh_from_arrays(vertices, faces, normals, albedo, "bake()");
        mesh = &*own;
    }
    SHPRT_CHECK(progress.is_none() || PyCallable_Check(progress.ptr()), invalid_argument,
                "progress: expected a callable progress(done, total), got {}",
                py::str(py::type::of(progress).attr("__name__")).cast<std::string>());

    // Runs on the calling thread only (see the top of the file). An exception from Python —
    // the callback's own, or KeyboardInterrupt from a signal — stops the bake and is re-raised
    // once bake() has returned; returning False stops it with shprt.Error(cancelled).
    std::exception_ptr python_error;
    options.progress = [&](const ProgressInfo& info) {
        py::gil_scoped_acquire acquire;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (progress.is_none()) return true;
            const py::object r = progress(info.done, info.total);
            return r.is_none() || r.cast<bool>();
        } catch (...) {
            python_error = std::current_exception();
            return false;
        }
    };
    TransferSet result;
    try {
        py::gil_scoped_release release;
        result = bake(*mesh, options);
    } catch (const Error& e) {
        if (python_error && e.code() == ErrorCode::cancelled) std::rethrow_exception(python_error);
        throw;
    }
    const std::size_t rows = result.receiver_count();
    std::vector<py::ssize_t> shape{py::ssize_t(rows)};
    if (result.layout.channels != 1) shape.push_back(result.layout.channels);
    shape.push_back(py::ssize_t(result.layout.floats_per_channel()));
    return take_vector(std::move(result.coeffs), std::move(shape));
}

}  // namespace

void bind_bake(py::module_& m) {
    m.def("bake", &bake_py, "vertices"_a, "faces"_a = py::none(), "normals"_a = py::none(),
          "albedo"_a = py::none(), py::kw_only(), "bands"_a = py::none(), "coeffs"_a = py::none(),
          "samples"_a = 1024, "sampler"_a = "sobol", "transfer"_a = "shadowed", "seed"_a = 1,
          "bounces"_a = 1, "tolerance"_a = 1e-4, "two_sided"_a = false, "indirect_samples"_a = 0,
          "source_spacing"_a = py::none(), "threads"_a = 0, "device"_a = "cpu",
          "progress"_a = py::none(),
          R"(Bakes per-vertex SH transfer (bake/bake.hpp) and returns it as a float32 array of
shape (V, K) — (V, 3, K) for RGB transfer — with K = bands² or coeffs (default 16).

vertices (V, 3) float and faces (T, 3) int, or a shprt.Mesh as the only positional argument.
normals=None computes them; albedo=None is 0.8 grey. samples S directions per vertex from
sampler 'sobol' (default), 'uniform' (the paper's), 'stratified' or 'fibonacci' with seed;
transfer 'shadowed' (default), 'unshadowed' or 'interreflected' (RGB, shape (V, 3, K); with
bounces N or 'converged' until the largest relative change is under tolerance, two_sided,
indirect_samples (0 = the default) and source_spacing (metres, 'vertices' or None = the
default): docs/interreflection.md); threads 0 = all; device 'cpu', 'cuda' or 'auto'. The same options and
seed give the same bits as `shprt bake`.

The GIL is released while it runs. progress(done, total) is called on this thread about 20
times a second (an interreflected bake reports its rays, then the bounces' rows, each from 0 to
its total); returning False cancels (shprt.Error with code 'cancelled'), raising cancels
and re-raises; Ctrl-C cancels too.)");
}

}  // namespace shprt::python
