// Bounce sources: where the light leaving a hit point comes from in interreflected transfer
// (interreflect.hpp; docs/interreflection.md, "Bounce sources").
//
// A ray of the operator hits a triangle at h; the light h sends is interpolated from points
// around it. Interpolating the hit triangle's *vertices* (the discretisation before issue 34)
// depends on how large the triangles are and carries light across geometry: a floor triangle
// whose far vertex lies below the floor, or a wall quad that runs on into its neighbour panel,
// brings the light of the outside into the room. So the sources are their own point set:
//
//  * a grid per triangle: triangle t is cut into n_t × n_t cells (n_t = ⌈longest edge / spacing⌉,
//    1 where the triangle is small enough), and the light at h is interpolated over the corners
//    of the cell that holds h (transport_build.hpp: grid_cell, grid_point_index). The grid's
//    corners are the mesh's vertices, so the receivers are sources [0, V) and their rows of the
//    operator are the bake's final gather; a triangle's other points are its own (not shared with
//    its neighbours: a crease keeps the normal of each side);
//  * two-sided surfaces (--two-sided): every point has a back copy (index + front), with the
//    normal negated, lit by what its own side sees; a ray that meets a back face interpolates
//    the back copies. So a back face reflects the light on its side, as a renderer does, and a
//    point inside closed geometry sees only the dark inside;
//  * validity: a point whose rays meet back faces — near it (within twice its cell size) for
//    more than kSourceNearBackShare of them, or at any distance for more than
//    kSourceBackShare — lies inside or under geometry (a vertex below the floor, the end of a
//    wall panel inside its neighbour). Its light is not the light of the surface a ray sees, so
//    before each bounce it is replaced by the mean of its valid neighbours' (a fill over the
//    grid's cells, ring by ring, as lightmappers dilate invalid texels), or zero when none is
//    within kSourceFillRings rings.
#pragma once

#include "shprt/bake/transport_build.hpp"
#include "shprt/core/vec.hpp"
#include "shprt/scene/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

// A point is invalid when more than this share of its rays meet a back face within twice its
// cell size, or more than kSourceBackShare of them a back face at any distance.
inline constexpr float kSourceNearBackShare = 0.1f;
inline constexpr float kSourceBackShare = 0.5f;
// How many rings of neighbours the fill searches for valid points before it gives up (zero).
inline constexpr int kSourceFillRings = 8;
// The sources that are not receivers (the grids' own points, the back copies) trace the first
// 1/kInnerSourceShare of the receivers' indirect directions, on the sphere (their T_0 is projected
// from the same rays): the receivers' rows are the final gather, whose noise is what a user sees;
// an inner source's light reaches a receiver averaged over the many hits of its row (measured:
// docs/interreflection.md, "Final gather").
inline constexpr std::size_t kInnerSourceShare = 2;
// The default spacing: the scene's bounding-box diagonal over this many cells.
inline constexpr float kDefaultSourceCells = 48.0f;

struct BounceSources {
    std::size_t vertices = 0;  // V: points [0, V) are the mesh's vertices (the receivers)
    std::size_t front = 0;     // points on the front sides; back copies follow when two-sided
    bool two_sided = false;
    float spacing = 0;  // the cell size asked for (metres; infinity: the mesh's vertices only)
    std::vector<Vec3f> positions, normals;  // per point (back copies: normals negated)
    std::vector<float> reach;               // per point: validity's distance, 2 × its cell size
    std::vector<std::uint32_t> grid;        // per triangle: cells per edge n ≥ 1
    std::vector<std::uint32_t> base;        // per triangle: its first own point (n > 1)

    std::size_t size() const { return positions.size(); }
    // The view A's entries read (valid while `mesh` and this are).
    TransportMeshView view(const Mesh& mesh) const;
};

// bounding-box diagonal / kDefaultSourceCells (1 for an empty or degenerate box).
float default_source_spacing(const Mesh& mesh);

// The sources of `mesh` (positions, unit normals per vertex) with cells of at most `spacing`
// metres (> 0; infinity: the vertices alone), and back copies when `two_sided`. Throws
// Error(invalid_argument) for a spacing that is not positive and Error(out_of_memory) when the
// points would pass 2^31 − 1.
BounceSources make_bounce_sources(const Mesh& mesh, float spacing, bool two_sided);

// How many points make_bounce_sources(mesh, spacing, two_sided) makes, without making them.
std::size_t bounce_source_count(const Mesh& mesh, float spacing, bool two_sided);

// Whether a point whose `rays` rays met `back` back faces, `near_back` of them within its reach,
// is a valid source (see the top).
bool source_is_valid(std::uint32_t rays, std::uint32_t back, std::uint32_t near_back);

// The fill of invalid points: round r sets each of its points to the mean of its neighbours
// (valid, or filled in an earlier round), which makes the rounds independent within themselves;
// points left over are zeroed. Deterministic: fixed rounds, fixed neighbour order.
struct SourceFill {
    struct Round {
        std::vector<std::uint32_t> point;      // the points this round fills
        std::vector<std::uint32_t> start;      // point.size() + 1 offsets into neighbour
        std::vector<std::uint32_t> neighbour;  // the points each takes the mean of
    };
    std::vector<Round> rounds;
    std::vector<std::uint32_t> zeroed;  // invalid points with no valid point within reach
    std::size_t invalid = 0;            // invalid points, filled or zeroed

    // Applies the fill to rows of `row_floats` floats each (point q's row at q·row_floats).
    void apply(float* rows, std::size_t row_floats, int threads) const;
};

// The fill of `sources` given each point's validity (1 = valid), over the grid's cells.
SourceFill plan_source_fill(const Mesh& mesh, const BounceSources& sources,
                            const std::vector<std::uint8_t>& valid);

}  // namespace shprt
