// Whole-mesh operations every scene source goes through: normals, validation, bounds.
#pragma once

#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <optional>
#include <string>

namespace shprt {

// Albedo of surfaces whose file gives no colour, and of the small built-in scenes (linear RGB).
constexpr float kDefaultAlbedo = 0.8f;

// Replaces mesh.normals with smooth per-vertex normals: each triangle adds its face normal to its
// three vertices, weighted by the triangle's area times the triangle's angle at that vertex
// (Max 1999 / Thürmer–Wüthrich 1998 angle weighting, scaled by area so slivers count little).
// Vertices are grouped by index: duplicated vertices at a hard edge keep their own normals.
// Sums are accumulated in double, in triangle order (deterministic). A vertex that no triangle
// uses, or whose weighted sum is zero, gets +Y. Precondition: indices in range (validate_mesh).
void compute_vertex_normals(Mesh& mesh);

// As compute_vertex_normals, but vertices at bit-identical positions share one normal, so a mesh
// that an importer "unindexed" (OBJ, STL: one vertex per triangle corner) is shaded smoothly as
// if it had been welded. Vertex order and count are unchanged.
void compute_vertex_normals_by_position(Mesh& mesh);

// Checks a mesh before anything traces or bakes it, and repairs what is harmless:
//   throws Error(format) naming `name` when the mesh has no vertices or no triangles, a position,
//   normal or albedo that is NaN or infinite, a triangle index >= vertex_count(), or a BRDF index
//   that is neither kNoBrdf nor < brdfs.size();
//   throws Error(invalid_argument) when normals/albedo/source_vertex/uvs/parents/brdf_index are
//   neither empty nor one per vertex, or when there are more than 2^32 - 1 vertices;
//   drops degenerate triangles (a repeated index, or zero area computed in double) and reports
//   their count with log_warn; throws Error(format) if none are left;
//   clamps albedo to [0, 1].
// `name` is the file path or "builtin:NAME" used in messages.
void validate_mesh(Mesh& mesh, const std::string& name);

// The first vertex whose BRDF index is neither Mesh::kNoBrdf nor below brdfs.size(), if any
// (the check every reader of Mesh::brdf_index makes, each with its own error).
std::optional<std::size_t> bad_brdf_index(const Mesh& mesh);

// The first vertex whose albedo has a channel outside [0, 1] (or NaN), if any: validate_mesh
// clamps every albedo into [0, 1], so the .shprt writer and reader refuse anything else.
std::optional<std::size_t> bad_albedo(const Mesh& mesh);

// The first vertex whose normal is zero (or not finite), if any: what the .shprt writer and reader
// refuse (computed normals are unit vectors; a vertex without faces gets +Y).
std::optional<std::size_t> zero_normal(const Mesh& mesh);

// The materials' BRDFs with their vertex counts, for people: "phong:32 (1200 vertices), ggx:0.4
// (300 vertices), none (50 vertices)"; "none" for a mesh without them.
std::string describe_brdfs(const Mesh& mesh);

// Axis-aligned bounds of all vertex positions (used or not), in the mesh's units (metres for the
// generated scenes). An empty mesh gives lo = hi = (0, 0, 0).
struct Bounds {
    Vec3f lo, hi;
};
Bounds mesh_bounds(const Mesh& mesh);

// Total triangle area (square metres for the generated scenes), summed in double. Precondition:
// indices in range (validate_mesh).
double mesh_surface_area(const Mesh& mesh);

// "N vertices, M triangles\nbounds: [..] .. [..]\nsurface area: A\n": what `shprt scene info`
// and the commands that write a scene print about it.
std::string describe(const Mesh& mesh);

}  // namespace shprt
