// shprt.Mesh, load_scene, builtin_scenes (scene/), shprt.File, load, save (io/shprt_file.hpp).
#include "bindings.hpp"
#include "convert.hpp"

#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/transfer/cpca.hpp"
#include "shprt/transfer/cpca_summary.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <pybind11/stl.h>

namespace shprt::python {

using namespace pybind11::literals;

Mesh mesh_from_arrays(py::handle vertices, py::handle faces, py::handle normals, py::handle albedo,
                      const char* name) {
    Mesh mesh;
    mesh.positions = vec3_rows(vertices, "vertices", "(V, 3)");
    mesh.triangles = triangle_rows(faces, "faces");
    if (!normals.is_none()) mesh.normals = vec3_rows(normals, "normals", "(V, 3)");
    if (!albedo.is_none())
        mesh.albedo = vec3_rows(albedo, "albedo", "(V, 3)");
    else
        mesh.albedo.assign(mesh.positions.size(),
                           Vec3f{kDefaultAlbedo, kDefaultAlbedo, kDefaultAlbedo});
    mesh.source = name;
    validate_mesh(mesh, name);
    if (mesh.normals.empty()) compute_vertex_normals(mesh);
    return mesh;
}

namespace {

py::ssize_t ssize(std::size_t n) { return static_cast<py::ssize_t>(n); }

template <class V>
py::array rows_view(V& rows, py::ssize_t cols, py::handle base) {
    using T = std::remove_reference_t<decltype(rows[0][0])>;
    return view_of(reinterpret_cast<T*>(rows.data()), {ssize(rows.size()), cols}, base);
}

// The transfer's array shape: (rows, [channels,] floats per channel), the channel axis only
// for more than one channel; a matrix channel is (K, K).
std::vector<py::ssize_t> transfer_shape(const TransferLayout& layout, std::size_t rows) {
    std::vector<py::ssize_t> shape{ssize(rows)};
    for (const std::size_t n : receiver_shape(layout)) shape.push_back(ssize(n));
    return shape;
}

// A File from a mesh and an array (V, K) or (V, C, K) of vector transfer, or, for kind 'glossy',
// (V, K(K+1)/2): each vertex's symmetric K×K matrix as its packed upper triangle (what
// bake(transfer='glossy') returns).
ShprtFile make_file(const Mesh& mesh, py::handle transfer, const std::string& kind,
                    const std::string& sampler, int samples, std::uint64_t seed,
                    const std::string& encoding) {
    const auto a = float32_array(transfer, "transfer");
    SHPRT_CHECK(a.ndim() == 2 || a.ndim() == 3, invalid_argument,
                "transfer: expected an array of shape (V, K) or (V, 3, K), got {}",
                describe_shape(a));
    ShprtFile file;
    file.mesh = mesh;
    TransferSet& t = file.transfer;
    t.kind = parse_transfer_kind(kind);
    t.sampler = parse_sampler_kind(sampler);
    t.samples = samples;
    t.seed = seed;
    t.layout.channels = a.ndim() == 3 ? int(a.shape(1)) : 1;
    t.layout.K = int(a.shape(a.ndim() - 1));
    // A matrix kind's row is its channel's matrix, packed as the kind table's shape says.
    const TransferKindRow& row = kind_row(t.kind);
    if (is_matrix(row)) {
        const int K = basis_size_of(row.shape, std::size_t(a.shape(a.ndim() - 1)));
        SHPRT_CHECK(a.ndim() == 2 && row.channels == 1 && K >= 1, invalid_argument,
                    "transfer: kind '{}' expects (V, K(K+1)/2), each vertex's symmetric "
                    "matrix packed, got {}",
                    row.name, describe_shape(a));
        t.layout.shape = row.shape;
        t.layout.K = K;
    }
    t.layout.encoding = parse_transfer_encoding(encoding);
    t.layout.validate();
    t.coeffs.assign(a.data(), a.data() + a.size());
    t.check(file.mesh);
    return file;
}

// A per-receiver array of a file's transfer (an error-bounded bake's estimates) as a view that
// keeps the file alive; None when the file has none.
template <auto Member>
py::object per_receiver_view(py::object self) {
    auto& values = self.cast<ShprtFile&>().transfer.*Member;
    if (values.empty()) return py::none();
    return view_of(values.data(), {py::ssize_t(values.size())}, self);
}

}  // namespace

void bind_scene(py::module_& m) {
    py::class_<Mesh>(m, "Mesh", R"(A triangle mesh as the library sees it (scene/mesh.hpp).

Its arrays are views of the library's memory (no copies): positions, normals, albedo (V, 3)
float32 and triangles (T, 3) uint32, counter-clockwise = front face, world space +Y up.)")
        .def(py::init([](ArrayLike vertices, ArrayLike faces, OptionalArrayLike normals,
                         OptionalArrayLike albedo) {
                 return mesh_from_arrays(vertices, faces, normals, albedo, "mesh");
             }),
             "vertices"_a, "faces"_a, "normals"_a = py::none(), "albedo"_a = py::none(),
             "A mesh from arrays; normals=None computes area- and angle-weighted vertex normals, "
             "albedo=None is 0.8 grey. Raises shprt.Error for bad shapes, dtypes, NaN or "
             "out-of-range indices.")
        .def_property_readonly(
            "positions",
            [](py::object self) { return rows_view(self.cast<Mesh&>().positions, 3, self); })
        .def_property_readonly(
            "normals",
            [](py::object self) { return rows_view(self.cast<Mesh&>().normals, 3, self); })
        .def_property_readonly(
            "albedo", [](py::object self) { return rows_view(self.cast<Mesh&>().albedo, 3, self); })
        .def_property_readonly(
            "triangles",
            [](py::object self) { return rows_view(self.cast<Mesh&>().triangles, 3, self); })
        .def_property_readonly("source", [](const Mesh& mesh) { return mesh.source; })
        .def_property_readonly("vertex_count", &Mesh::vertex_count)
        .def_property_readonly("triangle_count", &Mesh::triangle_count)
        .def("__repr__", [](const Mesh& mesh) {
            return fmt::format("shprt.Mesh('{}', {} vertices, {} triangles)", mesh.source,
                               mesh.vertex_count(), mesh.triangle_count());
        });

    m.def(
        "load_scene",
        [](const std::string& spec) {
            py::gil_scoped_release release;
            return load_scene(spec);
        },
        "spec"_a,
        "Loads a mesh file (PLY keeps its vertex order; OBJ, glTF, ... through Assimp) or "
        "'builtin:NAME' (scene/load.hpp) as a shprt.Mesh.");
    m.def("builtin_scenes", &builtin_scene_names, "The names 'builtin:NAME' accepts.");
}

void bind_io(py::module_& m) {
    py::class_<ShprtFile>(m, "File", R"(A baked scene: a .shprt file's mesh, transfer and metadata.

transfer is a view (no copy) of shape (V, K), or (V, C, K) for C = 3 channels, or (V, K(K+1)/2)
for glossy matrices (each vertex's packed upper triangle), float32.)")
        .def(py::init([](const Mesh& mesh, ArrayLike transfer, const std::string& kind,
                         const std::string& sampler, int samples, std::uint64_t seed,
                         const std::string& encoding) {
                 return make_file(mesh, transfer, kind, sampler, samples, seed, encoding);
             }),
             "mesh"_a, "transfer"_a, "kind"_a = "shadowed", "sampler"_a = "sobol", "samples"_a = 0,
             "seed"_a = 0, "encoding"_a = "float32",
             "A file's content from a mesh and per-vertex transfer (V, K) or (V, 3, K) — for "
             "kind 'glossy', (V, K(K+1)/2), the packed matrices bake(transfer='glossy') "
             "returns — with the bake's description (kind, sampler, samples, seed) for the "
             "metadata (save() takes samples = 0 only for kind 'unshadowed', a closed-form "
             "transfer: other kinds are baked from at least one direction); "
             "encoding 'float32' or 'float16' is how save() stores the coefficients.")
        .def_property_readonly(
            "mesh", [](ShprtFile& f) -> Mesh& { return f.mesh; },
            py::return_value_policy::reference_internal)
        .def_property_readonly(
            "transfer",
            [](py::object self) {
                auto& f = self.cast<ShprtFile&>();
                return view_of(f.transfer.coeffs.data(),
                               transfer_shape(f.transfer.layout, f.transfer.receiver_count()),
                               self);
            })
        .def_property_readonly(
            "direct",
            [](py::object self) -> py::object {
                auto& f = self.cast<ShprtFile&>();
                if (f.transfer.direct.empty()) return py::none();
                const auto V = py::ssize_t(f.transfer.receiver_count());
                return view_of(f.transfer.direct.data(), {V, py::ssize_t(f.transfer.layout.K)},
                               self);
            },
            "An interreflected bake's direct part T_0 (V, K), one channel (the shadowed "
            "transfer), a view; None for other files.")
        .def_property_readonly("K", [](const ShprtFile& f) { return f.transfer.layout.K; })
        .def_property_readonly("channels",
                               [](const ShprtFile& f) { return f.transfer.layout.channels; })
        .def_property_readonly("kind",
                               [](const ShprtFile& f) { return to_string(f.transfer.kind); })
        .def_property_readonly("sampler",
                               [](const ShprtFile& f) { return to_string(f.transfer.sampler); })
        .def_property_readonly("samples", [](const ShprtFile& f) { return f.transfer.samples; })
        .def_property_readonly("seed", [](const ShprtFile& f) { return f.transfer.seed; })
        .def_property_readonly(
            "target_error", [](const ShprtFile& f) { return f.transfer.target_error; },
            "An error-bounded bake's bound E (0: none; docs/sampling.md).")
        .def_property_readonly(
            "receiver_samples", &per_receiver_view<&TransferSet::receiver_samples>,
            "An error-bounded bake's directions per receiver (R,) uint32, a view; None for other "
            "files (every receiver has `samples`).")
        .def_property_readonly(
            "receiver_error", &per_receiver_view<&TransferSet::receiver_error>,
            "An error-bounded bake's estimated error per receiver (R,) float32, a view; None for "
            "other files.")
        .def_property_readonly(
            "encoding", [](const ShprtFile& f) { return to_string(f.transfer.layout.encoding); })
        .def_property_readonly("metadata_json", [](const ShprtFile& f) { return f.metadata_json; })
        .def("summary", &shprt_summary, "What `shprt info` prints.")
        .def("__repr__", [](const ShprtFile& f) {
            return fmt::format("shprt.File('{}', {} vertices, K={}, {} channel(s), {})",
                               f.mesh.source, f.mesh.vertex_count(), f.transfer.layout.K,
                               f.transfer.layout.channels, to_string(f.transfer.kind));
        });

    m.def(
        "compress",
        [](const ShprtFile& file, int clusters, int vectors, bool half, std::uint64_t seed,
           int iterations, int threads, std::optional<std::pair<int, int>> probe_cpca) {
            CpcaOptions options;
            options.clusters = clusters;
            options.vectors = vectors;
            options.seed = seed;
            options.iterations = iterations;
            options.threads = threads;
            SetCompression s;
            {
                py::gil_scoped_release release;
                s = compress_set(file.transfer, receiver_normals(file.mesh, file.transfer),
                                 cpca_fits(options, probe_cpca), half, std::nullopt, std::nullopt,
                                 "probe_cpca");
            }
            CpcaResult& r = s.rows;
            const std::optional<ProbeCpcaResult>& probes = s.probes;
            ShprtFile out;
            out.mesh = file.mesh;
            out.transfer = std::move(s.rows.compressed);
            py::dict report;
            if (probes) {
                report["probe_relative_rmse"] = probes->relative_rmse;
                report["bytes_per_probe"] = probes->bytes_per_probe;
                report["raw_bytes_per_probe"] = probes->raw_bytes_per_probe;
            }
            report["relative_rmse"] = r.error.relative_rmse;
            report["receiver_rmse"] = take_vector(std::move(r.error.receiver_rmse),
                                                  {py::ssize_t(out.transfer.receiver_count())});
            report["worst"] = r.error.worst;
            report["bytes_per_receiver"] = r.bytes_per_receiver;
            report["raw_bytes_per_receiver"] = r.raw_bytes_per_receiver;
            report["direct_bytes_per_receiver"] = r.direct_bytes_per_receiver;
            report["seconds"] = r.seconds_fit + r.seconds_error;
            return py::make_tuple(std::move(out), report);
        },
        "file"_a, "clusters"_a, "vectors"_a, py::kw_only(), "half"_a = false, "seed"_a = 1,
        "iterations"_a = 16, "threads"_a = 0, "probe_cpca"_a = py::none(),
        R"(Clustered PCA of a file's transfer rows (transfer/cpca.hpp), as `shprt compress`: returns
(File, report). The File carries the code (save() writes a CPCA file; its transfer holds the
rebuilt rows) and keeps an interreflected file's direct part. The report: relative_rmse of exit
radiance under the test lights (and views, for matrices), receiver_rmse per receiver, the worst
receivers, and bytes per receiver for the code, the raw rows and the kept direct part.
probe_cpca=(clusters, vectors) compresses the file's transfer probes too (`--probe-cpca`); the
report then has probe_relative_rmse (of the incident radiance under lights of unit
coefficients), bytes_per_probe and raw_bytes_per_probe.)");
    m.def(
        "load",
        [](const std::string& path) {
            py::gil_scoped_release release;
            return read_shprt(path);
        },
        "path"_a, "Reads and validates a .shprt file (io/shprt_file.hpp) as a shprt.File.");
    m.def(
        "save",
        [](const std::string& path, const ShprtFile& file, bool reproducible) {
            WriteOptions options;
            options.reproducible = reproducible;
            py::gil_scoped_release release;
            write_shprt(path, file.mesh, file.transfer, options);
        },
        "path"_a, "file"_a, "reproducible"_a = false,
        "Writes a shprt.File atomically (no half-written file on error).");
    m.def(
        "save",
        [](const std::string& path, const Mesh& mesh, ArrayLike transfer, const std::string& kind,
           const std::string& sampler, int samples, std::uint64_t seed, const std::string& encoding,
           bool reproducible) {
            const ShprtFile file =
                make_file(mesh, transfer, kind, sampler, samples, seed, encoding);
            WriteOptions options;
            options.reproducible = reproducible;
            py::gil_scoped_release release;
            write_shprt(path, file.mesh, file.transfer, options);
        },
        "path"_a, "mesh"_a, "transfer"_a, "kind"_a = "shadowed", "sampler"_a = "sobol",
        "samples"_a = 0, "seed"_a = 0, "encoding"_a = "float32", "reproducible"_a = false,
        "Writes a mesh and its transfer (V, K) or (V, 3, K) as a .shprt file; samples is the "
        "bake's directions per receiver, 0 only for kind 'unshadowed' computed in closed form "
        "(readers refuse 0 for any other kind).");
}

}  // namespace shprt::python
