// shprt.bake (bake/bake.hpp): the GIL is released while the library bakes; the library calls
// BakeOptions::progress only from the thread that called bake() (src/bake/bake_progress.hpp), which
// is the Python thread that called shprt.bake, so the callback takes the GIL back there and runs
// the Python function. No worker thread ever touches Python.
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/bake/bake_option_table.hpp"
#include "shprt/bake/request.hpp"
#include "shprt/bake/request_options.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <exception>
#include <limits>
#include <optional>

namespace shprt::python {

using namespace pybind11::literals;

namespace {

// The keywords that are the bake options (bake/bake_option_table.hpp): filled into the library's
// BakeOptionChoice, as the command line fills it, and checked by the same bake_options_from.
struct OptionKeywords {
    BakeOptionChoice choice;
    py::object bounces, source_spacing;  // int or str; float or str (None: unset)
};

BakeOptions bake_options(OptionKeywords k) {
    BakeOptionChoice& c = k.choice;
    // bounces N or 'converged', source_spacing metres or 'vertices': the command line's text.
    if (py::isinstance<py::str>(k.bounces)) {
        c.bounces = k.bounces.cast<std::string>();
    } else if (!k.bounces.is_none()) {
        SHPRT_CHECK(py::isinstance<py::int_>(k.bounces) && !py::isinstance<py::bool_>(k.bounces),
                    invalid_argument, "bounces: expected an int or 'converged', got {}",
                    py::str(py::type::of(k.bounces).attr("__name__")).cast<std::string>());
        c.bounces = py::str(k.bounces).cast<std::string>();
    }
    if (py::isinstance<py::str>(k.source_spacing))
        c.source_spacing = k.source_spacing.cast<std::string>();
    else if (!k.source_spacing.is_none())
        c.source_spacing = fmt::format("{}", k.source_spacing.cast<double>());
    return bake_options_from(c, Spelling::python);
}

// The receiver keywords, parsed by the library's one parser (bake/request.hpp: parse_receivers),
// as `shprt bake` parses its options.
struct Receivers {
    std::string domain;
    py::object resolution, shard;
    int uv_set = 0;
    std::optional<double> refine;
    std::optional<long long> max_vertices, max_edge_split_depth;
    bool unwrap = false;
    std::optional<double> texel_density;
    py::object probes, probe_box;
    std::optional<long long> probe_bands;
};
// The output keywords: a .shprt file (with its encoding, streaming, reproducibility), the
// checkpoint, the memory limit.
struct Output {
    std::optional<std::string> path, checkpoint, resume;
    bool half = false, float32 = false, stream = false, reproducible = false;
    double checkpoint_every = 30;
    py::object max_memory;
};

// A str or an os.PathLike as a path; None as none.
std::optional<std::string> path_of(const py::object& value) {
    if (value.is_none()) return std::nullopt;
    return py::module_::import("os").attr("fspath")(value).cast<std::string>();
}

// 8, (8, 4) or "8x4" as the command line's "W[xH]"; (0, 4) or "0/4" as its "I/N".
std::string spelled(const py::object& value, const char* separator, const char* name) {
    if (value.is_none()) return {};
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    if (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value))
        return std::to_string(value.cast<long long>());
    if (py::isinstance<py::tuple>(value) && py::len(value) == 2)
        return std::to_string(value.cast<py::tuple>()[0].cast<long long>()) + separator +
               std::to_string(value.cast<py::tuple>()[1].cast<long long>());
    fail(ErrorCode::invalid_argument, "{}: expected a str, an int or a pair, got {}", name,
         py::str(py::type::of(value).attr("__name__")).cast<std::string>());
}

// "auto", "16,8,16:0.5", (16, 8, 16) or a box's six numbers as the command line's text (None:
// empty); a tuple of `count` numbers.
std::string spelled_probes(const py::object& value, const char* name, std::size_t count) {
    if (value.is_none()) return {};
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    if ((py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) &&
        py::len(value) == count) {
        std::string text;
        for (const py::handle item : value) {
            if (!text.empty()) text += ',';
            text += py::str(item).cast<std::string>();
        }
        return text;
    }
    fail(ErrorCode::invalid_argument, "{}: expected a str or {} numbers, got {}", name, count,
         py::str(py::repr(value)).cast<std::string>());
}

void fill_request(const Receivers& rx, const Output& out, BakeRequest& request) {
    ReceiverChoice choice;
    choice.domain = rx.domain;
    choice.resolution = spelled(rx.resolution, "x", "resolution");
    choice.uv_set = rx.uv_set;
    choice.refine = rx.refine;
    choice.max_vertices = rx.max_vertices;
    choice.max_edge_split_depth = rx.max_edge_split_depth;
    choice.shard = spelled(rx.shard, "/", "shard");
    choice.unwrap = rx.unwrap;
    choice.texel_density = rx.texel_density;
    request.receivers = parse_receivers(choice);
    request.probes = parse_probes(spelled_probes(rx.probes, "probes", 3),
                                  spelled_probes(rx.probe_box, "probe_box", 6), rx.probe_bands);
    const bool texels = std::holds_alternative<TexelGrid>(request.receivers);
    SHPRT_CHECK(!out.float32 || texels, invalid_argument, "float32=True needs domain='texel'");
    SHPRT_CHECK(
        out.path || (!texels && !std::holds_alternative<RefinedVertices>(request.receivers)),
        invalid_argument,
        "a texel or refined bake writes a .shprt file (its atlas or its new mesh go "
        "with the rows): give output=, then read it with shprt.load");
    SHPRT_CHECK(out.path || !request.probes, invalid_argument,
                "probes: the probes are written into the .shprt file beside the rows: give "
                "output=, then read it with shprt.load");
    SHPRT_CHECK(out.path || (!out.half && !out.stream && !out.reproducible), invalid_argument,
                "half, stream and reproducible describe the file: give output=");
    if (out.path)
        request.output =
            file_output_from(*out.path, {out.half, out.stream, out.reproducible}, out.float32);
    SHPRT_CHECK(!(out.checkpoint && out.resume), invalid_argument,
                "checkpoint and resume: give one (resume continues the checkpoint it names)");
    if (out.checkpoint || out.resume)
        request.checkpoint = CheckpointRequest{out.checkpoint ? *out.checkpoint : *out.resume,
                                               bool(out.resume), out.checkpoint_every};
    if (!out.max_memory.is_none())
        apply_max_memory(spelled(out.max_memory, "", "max_memory"), request, Spelling::python);
    check(request);
}

// What a bake into a file returns: where it went and what it took.
py::dict summary(const BakeResult& r, const BakeRequest& request) {
    py::dict d;
    d["path"] = request.output->path;
    d["first"] = r.first;
    d["receivers"] = r.receivers;
    d["K"] = r.info.layout.K;
    d["samples"] = r.info.samples;
    d["encoding"] = std::string(to_string(r.info.layout.encoding));
    d["seconds_bake"] = r.seconds_bake;
    d["seconds_write"] = r.seconds_write;
    d["estimated_bytes"] = r.estimated_bytes;
    d["peak_bytes"] = r.info.stats.peak_bytes_host;
    if (std::holds_alternative<TexelGrid>(request.receivers))
        d["covered_texels"] = r.covered_texels;
    if (r.unwrap) {  // the atlas unwrap=True made (scene/uv_atlas.hpp)
        py::dict u;
        u["charts"] = r.unwrap->charts;
        u["resolution"] = r.unwrap->resolution;
        u["texels_per_metre"] = r.unwrap->texels_per_metre;
        u["max_stretch"] = r.unwrap->max_stretch;
        u["mean_stretch"] = r.unwrap->mean_stretch;
        u["added_vertices"] = r.unwrap->added_vertices;
        u["summary"] = describe(*r.unwrap);
        d["unwrap"] = u;
    }
    if (r.refined_mesh) d["vertices"] = r.refined_mesh->vertex_count();
    if (const ProbeGrid& g = r.transfer.probes; !g.empty()) {  // bake/probe_bake.hpp
        py::dict p;
        std::size_t valid = 0;
        for (std::uint8_t v : g.valid) valid += v;
        p["counts"] = py::make_tuple(g.counts[0], g.counts[1], g.counts[2]);
        p["origin"] = py::make_tuple(g.origin.x, g.origin.y, g.origin.z);
        p["spacing"] = py::make_tuple(g.spacing.x, g.spacing.y, g.spacing.z);
        p["K"] = g.K;
        p["channels"] = g.channels;
        p["valid"] = valid;
        p["summary"] = describe_probes(g);
        d["probes"] = p;
    }
    return d;
}

py::object bake_py(py::handle vertices, py::handle faces, py::handle normals, py::handle albedo,
                   OptionKeywords keywords, py::object progress, const Receivers& receivers,
                   const Output& out) {
    BakeRequest request;
    request.options = bake_options(std::move(keywords));
    fill_request(receivers, out, request);
    BakeOptions& options = request.options;
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
    // the callback's own, or KeyboardInterrupt from a signal — stops the bake and is re-raised,
    // as itself, once bake() has returned, whatever bake() did meanwhile (a last call at 100 %
    // that raises finds the bake already done; the stop may surface as another error). A return
    // value other than True, False or None is a TypeError, raised the same way; returning False
    // stops the bake with shprt.Error(cancelled).
    std::exception_ptr python_error;
    options.progress = [&](const ProgressInfo& info) {
        if (python_error) return false;
        py::gil_scoped_acquire acquire;
        try {
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (progress.is_none()) return true;
            const py::object r = progress(info.done, info.total);
            if (r.is_none()) return true;
            if (!PyBool_Check(r.ptr()))
                throw py::type_error(
                    "progress: the callback must return True, False or None, not " +
                    py::str(py::type::of(r).attr("__name__")).cast<std::string>());
            return r.ptr() == Py_True;
        } catch (...) {
            python_error = std::current_exception();
            return false;
        }
    };
    BakeResult result;
    try {
        py::gil_scoped_release release;
        result = run(request, *mesh);
    } catch (const Error&) {
        if (python_error) std::rethrow_exception(python_error);
        throw;
    }
    if (python_error) std::rethrow_exception(python_error);
    if (request.output) return summary(result, request);
    const TransferSet& t = result.transfer;
    std::vector<py::ssize_t> shape{py::ssize_t(t.receiver_count())};
    for (const std::size_t n : receiver_shape(t.layout)) shape.push_back(py::ssize_t(n));
    return take_vector(std::move(result.transfer.coeffs), std::move(shape));
}

}  // namespace

// The types bake()'s loosely typed arguments show in its signature (convert.hpp, Loose): what
// each one takes, checked in bake_options and fill_request.
#define SHPRT_PY_NAME(type, text)                                  \
    struct type {                                                  \
        static constexpr auto name = py::detail::const_name(text); \
    }
SHPRT_PY_NAME(MeshOrArrayName, "Union[shprt.Mesh, numpy.typing.ArrayLike]");
SHPRT_PY_NAME(BouncesName, "Union[int, str, None]");
SHPRT_PY_NAME(SpacingName, "Union[float, str, None]");
SHPRT_PY_NAME(ProgressName, "Optional[Callable[[int, int], Optional[bool]]]");
SHPRT_PY_NAME(SizeName, "Union[int, str, Tuple[int, int], None]");
SHPRT_PY_NAME(ProbesName, "Union[str, Tuple[int, int, int], None]");
SHPRT_PY_NAME(ProbeBoxName, "Union[str, Tuple[float, float, float, float, float, float], None]");
SHPRT_PY_NAME(PathName, "Union[str, os.PathLike[str], None]");
#undef SHPRT_PY_NAME
using Path = Loose<PathName>;
using Size = Loose<SizeName>;

void bind_bake(py::module_& m) {
    const BakeOptionChoice d;
    const ReceiverChoice rd;    // the receivers' defaults: receiver_option_table's
    const FileChoice fd;        // file_option_table's
    const CheckpointChoice cd;  // checkpoint_option_table's
    m.def(
        "bake",
        [](Loose<MeshOrArrayName> vertices, OptionalArrayLike faces, OptionalArrayLike normals,
           OptionalArrayLike albedo, std::optional<long long> bands,
           std::optional<long long> coeffs, long long samples, const std::string& sampler,
           const std::string& directions, double target_error, long long max_samples,
           const std::string& transfer, std::uint64_t seed, const Loose<BouncesName>& bounces,
           std::optional<double> tolerance, bool two_sided,
           std::optional<long long> indirect_samples, const Loose<SpacingName>& source_spacing,
           std::optional<long long> bounce_coeffs, long long threads, const std::string& device,
           Loose<ProgressName> progress, const std::string& domain, Size resolution, int uv_set,
           bool unwrap, std::optional<double> texel_density, std::optional<double> refine,
           std::optional<long long> max_vertices, std::optional<long long> max_edge_split_depth,
           Size shard, Loose<ProbesName> probes, Loose<ProbeBoxName> probe_box,
           std::optional<long long> probe_bands, const Path& output, bool half, bool float32,
           bool stream, bool reproducible, const Path& checkpoint, const Path& resume,
           double checkpoint_every, Size max_memory) {
            OptionKeywords keywords{{}, bounces.value, source_spacing.value};
            BakeOptionChoice& c = keywords.choice;
            c.bands = bands;
            c.coeffs = coeffs;
            c.samples = samples;
            c.sampler = sampler;
            c.directions = directions;
            c.target_error = target_error;
            c.max_samples = max_samples;
            c.transfer = transfer;
            c.seed = seed;
            c.tolerance = tolerance;
            c.two_sided = two_sided;
            c.indirect_samples = indirect_samples;
            c.bounce_coeffs = bounce_coeffs;
            c.threads = threads;
            c.device = device;
            const Receivers rx{domain,
                               std::move(resolution.value),
                               std::move(shard.value),
                               uv_set,
                               refine,
                               max_vertices,
                               max_edge_split_depth,
                               unwrap,
                               texel_density,
                               std::move(probes.value),
                               std::move(probe_box.value),
                               probe_bands};
            const Output out{path_of(output.value),
                             path_of(checkpoint.value),
                             path_of(resume.value),
                             half,
                             float32,
                             stream,
                             reproducible,
                             checkpoint_every,
                             std::move(max_memory.value)};
            return bake_py(vertices, faces, normals, albedo, std::move(keywords),
                           std::move(progress.value), rx, out);
        },
        "vertices"_a, "faces"_a = py::none(), "normals"_a = py::none(), "albedo"_a = py::none(),
        // The bake options' defaults are BakeOptionChoice's, the command line's (an unset one
        // is None).
        py::kw_only(), "bands"_a = py::none(), "coeffs"_a = py::none(), "samples"_a = d.samples,
        "sampler"_a = d.sampler, "directions"_a = d.directions, "target_error"_a = d.target_error,
        "max_samples"_a = d.max_samples, "transfer"_a = d.transfer, "seed"_a = d.seed,
        "bounces"_a = py::none(), "tolerance"_a = py::none(), "two_sided"_a = d.two_sided,
        "indirect_samples"_a = py::none(), "source_spacing"_a = py::none(),
        "bounce_coeffs"_a = py::none(), "threads"_a = d.threads, "device"_a = d.device,
        "progress"_a = py::none(), "domain"_a = rd.domain, "resolution"_a = py::none(),
        "uv_set"_a = rd.uv_set, "unwrap"_a = rd.unwrap, "texel_density"_a = py::none(),
        "refine"_a = py::none(), "max_vertices"_a = py::none(),
        "max_edge_split_depth"_a = py::none(), "shard"_a = py::none(), "probes"_a = py::none(),
        "probe_box"_a = py::none(), "probe_bands"_a = py::none(), "output"_a = py::none(),
        "half"_a = fd.half, "float32"_a = rd.float32, "stream"_a = fd.stream,
        "reproducible"_a = fd.reproducible, "checkpoint"_a = py::none(), "resume"_a = py::none(),
        "checkpoint_every"_a = cd.checkpoint_every, "max_memory"_a = py::none(),
        R"(Bakes per-vertex SH transfer (bake/bake.hpp) and returns it as a float32 array of
shape (V, K) — (V, 3, K) for RGB transfer — with K = bands² or coeffs (default 16; 25 for glossy).

vertices (V, 3) float and faces (T, 3) int, or a shprt.Mesh as the only positional argument.
normals=None computes them; albedo=None is 0.8 grey. samples S directions per vertex from
sampler 'sobol' (default), 'uniform' (the paper's), 'stratified' or 'fibonacci' with seed;
directions 'local' (default: one cosine-weighted set in each receiver's tangent frame, every ray
above the horizon) or 'sphere' (one set on the sphere, the paper's): docs/sampling.md;
target_error E (0 = off) gives each vertex the smallest nested prefix 128, 256, ... up to
max_samples (0 = 16384; samples is then not used) whose estimated relative error is at most E
(shadowed, unshadowed or interreflected, sobol or uniform, CPU: docs/sampling.md,
"Error-bounded bakes");
transfer 'shadowed' (default), 'unshadowed' or 'interreflected' (RGB, shape (V, 3, K); with
bounces N (None: 1) or 'converged' until the largest relative change is under tolerance
(None: 1e-4), two_sided, indirect_samples, source_spacing (metres or 'vertices') and
bounce_coeffs (the coefficients after the second bounce), None each for the default:
docs/interreflection.md); threads 0 = all; device 'cpu', 'cuda' or 'auto'. The options, their
defaults and limits are `shprt bake`'s (one table: bake/bake_option_table.hpp), and the same
options and seed give the same bits.

The rest is `shprt bake`'s, with the same names and values (bake/request.hpp):
receivers — shard 'I/N' or (I, N) (that part of the vertices: the array holds its rows);
domain 'texel' with resolution W, (W, H) or 'WxH' and uv_set, or unwrap=True (a new conformal
atlas, the file keeps the unwrapped mesh; the dict's 'unwrap' describes it) with resolution W or
texel_density (texels per metre); refine (a tolerance) with
max_vertices and max_edge_split_depth; probes 'auto', 'auto:S', 'NX,NY,NZ[:S]' or (NX, NY, NZ)
with probe_box (X0, Y0, Z0, X1, Y1, Z1) and probe_bands (default 3): transfer probes written into
the file beside the rows (needs output=; the dict's 'probes' describes them; docs/probes.md).
Output — output= a .shprt path writes the file (needed for
texels and refinement) and returns a dict (path, receivers, K, samples, encoding, seconds, ...)
in place of the array; with half, float32 (texels), stream (rows into the file as they finish)
and reproducible. checkpoint= a path keeps finished rows so that a cancelled bake continues with
resume= that path (bit for bit; checkpoint_every seconds between syncs); max_memory (bytes, or
'512M', '4G') refuses a bake whose estimate is larger (default: the available memory).

The GIL is released while it runs. progress(done, total) is called on this thread about 20
times a second (an interreflected bake reports its rays, then the bounces' rows, each from 0 to
its total); returning False cancels (shprt.Error with code 'cancelled'), raising cancels
and re-raises; Ctrl-C cancels too.)");
}

}  // namespace shprt::python
