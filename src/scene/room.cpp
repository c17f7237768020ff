// The paper's test scene (Sloan, Kautz and Snyder 2002 bake a furnished room; this is our own
// deterministic stand-in): a room with an open top, window and door openings, and furniture,
// tessellated by MeshBuilder grids whose cell size is solved for the requested triangle count.
#include "shprt/scene/room.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/scene/builder.hpp"
#include "shprt/scene/uv_atlas.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace shprt {
namespace {

constexpr double kW2 = kRoomHalfWidth, kD2 = kRoomHalfDepth;
constexpr double kH = kRoomWallHeight, kT = kRoomWallThickness;
constexpr double kSlab = double(kRoomCeilingTop) - double(kRoomWallHeight);

// Linear-RGB albedos.
constexpr Vec3f kFloorOak{0.32f, 0.20f, 0.10f};
constexpr Vec3f kWallPlaster{0.72f, 0.68f, 0.60f};
constexpr Vec3f kWallAccent{0.30f, 0.40f, 0.38f};  // the back wall, behind the shelf
constexpr Vec3f kWallOutside{0.60f, 0.58f, 0.55f};
constexpr Vec3f kCeilingWhite{0.80f, 0.80f, 0.78f};
constexpr Vec3f kRoofGrey{0.30f, 0.30f, 0.32f};
constexpr Vec3f kDarkWood{0.20f, 0.10f, 0.05f};
constexpr Vec3f kMidWood{0.30f, 0.16f, 0.07f};
constexpr Vec3f kLightWood{0.45f, 0.30f, 0.16f};
constexpr Vec3f kWalnut{0.16f, 0.09f, 0.05f};
constexpr Vec3f kSofaFabric{0.06f, 0.11f, 0.28f};
constexpr Vec3f kCushion{0.09f, 0.16f, 0.36f};
constexpr Vec3f kPillowOrange{0.60f, 0.25f, 0.05f};
constexpr Vec3f kRugRed{0.35f, 0.05f, 0.04f};
constexpr Vec3f kMetal{0.30f, 0.30f, 0.30f};
constexpr Vec3f kBlack{0.04f, 0.04f, 0.04f};
constexpr Vec3f kShade{0.70f, 0.62f, 0.45f};
constexpr Vec3f kTerracotta{0.45f, 0.16f, 0.07f};
constexpr Vec3f kLeaves{0.06f, 0.20f, 0.05f};
constexpr Vec3f kPorcelain{0.75f, 0.75f, 0.72f};
constexpr Vec3f kCanvas{0.60f, 0.30f, 0.10f};
constexpr std::array<Vec3f, 9> kBookColours = {{{0.35f, 0.04f, 0.03f},
                                                {0.03f, 0.06f, 0.20f},
                                                {0.05f, 0.18f, 0.06f},
                                                {0.50f, 0.33f, 0.05f},
                                                {0.60f, 0.55f, 0.40f},
                                                {0.03f, 0.03f, 0.03f},
                                                {0.03f, 0.20f, 0.22f},
                                                {0.20f, 0.03f, 0.06f},
                                                {0.25f, 0.25f, 0.25f}}};

// Counter-based generator (SplitMix64) so book sizes do not depend on any library's
// distribution implementation.
class SplitMix {
public:
    explicit SplitMix(std::uint64_t seed) : m_state(seed) {}
    double uniform(double lo, double hi) {
        m_state += 0x9E3779B97F4A7C15ull;
        std::uint64_t z = m_state;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return lo + (hi - lo) * static_cast<double>(z >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t m_state;
};

struct Cells {
    double fine;       // floor, inner walls, reveals, ceiling underside
    double furniture;  // everything standing in the room
    double coarse;     // outer faces, wall tops, roof
};

struct Opening {
    double u0, u1, v0, v1;  // along the wall from its start; height above the floor
};

// A wall in local coordinates: it runs along +X from 0 to `length`, its inner face is the plane
// z = 0 facing +Z (into the room), its outer face z = -kT. Outer faces reach kT past both ends
// and the tops of walls that `cover_corners` do too, so four walls close the corners exactly.
void add_wall(MeshBuilder& b, Vec3d start, double yaw, double length, bool cover_corners,
              std::span<const Opening> openings, bool top, Vec3f inner_albedo, const Cells& c) {
    b.set_placement(start, yaw);
    std::vector<Rect2> holes;  // z-axis rectangles: (a, b) = (x, y)
    for (const Opening& o : openings) holes.push_back({o.u0, o.u1, o.v0, o.v1});
    b.add_rect(Axis::z, 0.0, +1, {0.0, length, 0.0, kH}, c.fine, inner_albedo, holes);
    b.add_rect(Axis::z, -kT, -1, {-kT, length + kT, 0.0, kH}, c.coarse, kWallOutside, holes);
    const double ext = cover_corners ? kT : 0.0;
    if (top) b.add_rect(Axis::y, kH, +1, {-kT, 0.0, -ext, length + ext}, c.coarse, kWallOutside);
    for (const Opening& o : openings) {
        // Reveals: jambs (x-axis rectangles, (a, b) = (y, z)), head and sill ((a, b) = (z, x)).
        b.add_rect(Axis::x, o.u0, +1, {o.v0, o.v1, -kT, 0.0}, c.fine, inner_albedo);
        b.add_rect(Axis::x, o.u1, -1, {o.v0, o.v1, -kT, 0.0}, c.fine, inner_albedo);
        b.add_rect(Axis::y, o.v1, -1, {-kT, 0.0, o.u0, o.u1}, c.fine, inner_albedo);
        b.add_rect(Axis::y, o.v0, +1, {-kT, 0.0, o.u0, o.u1}, c.fine,
                   o.v0 == 0.0 ? kFloorOak : inner_albedo);  // a door's threshold is floor
    }
}

void add_shell(MeshBuilder& b, bool ceiling, const Cells& c) {
    b.reset_placement();
    b.add_rect(Axis::y, 0.0, +1, {-kD2, kD2, -kW2, kW2}, c.fine, kFloorOak);
    const Opening window{-1.8 + kW2, -0.2 + kW2, 0.9, 2.2};
    const Opening door{0.7 + kD2, 1.6 + kD2, 0.0, 2.1};
    const bool tops = !ceiling;  // under a ceiling the wall tops are hidden
    add_wall(b, {-kW2, 0, -kD2}, 0.0, 2 * kW2, true, {&window, 1}, tops, kWallAccent, c);  // back
    add_wall(b, {kW2, 0, kD2}, kPi, 2 * kW2, true, {}, tops, kWallPlaster, c);             // front
    add_wall(b, {-kW2, 0, kD2}, 0.5 * kPi, 2 * kD2, false, {}, tops, kWallPlaster, c);     // left
    add_wall(b, {kW2, 0, -kD2}, -0.5 * kPi, 2 * kD2, false, {&door, 1}, tops, kWallPlaster,
             c);  // right
    if (!ceiling) return;

    b.reset_placement();
    const double top = kH + kSlab;
    // Skylights as y-axis rectangles: (a, b) = (z, x).
    const std::array<Rect2, 2> skylights = {{{-0.6, 0.6, -2.2, -1.0}, {-0.6, 0.6, 0.2, 1.4}}};
    b.add_rect(Axis::y, kH, -1, {-kD2, kD2, -kW2, kW2}, c.fine, kCeilingWhite, skylights);
    b.add_rect(Axis::y, top, +1, {-kD2 - kT, kD2 + kT, -kW2 - kT, kW2 + kT}, c.coarse, kRoofGrey,
               skylights);
    for (int s : {-1, 1}) {
        b.add_rect(Axis::x, s * (kW2 + kT), s, {kH, top, -kD2 - kT, kD2 + kT}, c.coarse,
                   kWallOutside);
        b.add_rect(Axis::z, s * (kD2 + kT), s, {-kW2 - kT, kW2 + kT, kH, top}, c.coarse,
                   kWallOutside);
    }
    for (const Rect2& s : skylights) {
        b.add_rect(Axis::x, s.b0, +1, {kH, top, s.a0, s.a1}, c.fine, kCeilingWhite);
        b.add_rect(Axis::x, s.b1, -1, {kH, top, s.a0, s.a1}, c.fine, kCeilingWhite);
        b.add_rect(Axis::z, s.a0, +1, {s.b0, s.b1, kH, top}, c.fine, kCeilingWhite);
        b.add_rect(Axis::z, s.a1, -1, {s.b0, s.b1, kH, top}, c.fine, kCeilingWhite);
    }
}

// Four legs of size `leg` inset to the corners of [-hx, hx] x [-hz, hz], from y0 to y1.
void add_legs(MeshBuilder& b, double hx, double hz, double leg, double y0, double y1, double cell,
              Vec3f albedo) {
    for (double sx : {-1.0, 1.0})
        for (double sz : {-1.0, 1.0}) {
            const double x = sx * (hx - leg / 2), z = sz * (hz - leg / 2);
            b.add_box({x - leg / 2, y0, z - leg / 2}, {x + leg / 2, y1, z + leg / 2}, cell, albedo,
                      kBoxNoBottom);
        }
}

void add_dining_set(MeshBuilder& b, double cell) {
    b.set_placement({0.6, 0, 0.4});
    b.add_box({-0.8, 0.72, -0.45}, {0.8, 0.76, 0.45}, cell, kMidWood);
    add_legs(b, 0.74, 0.39, 0.06, 0.0, 0.72, cell, kMidWood);

    // Chairs face local +Z; the back is at -Z.
    struct Place {
        double x, z, yaw;
    };
    const std::array<Place, 4> chairs = {
        {{0.2, -0.3, 0.0}, {1.0, -0.3, 0.0}, {0.2, 1.1, kPi}, {1.05, 1.25, kPi - 0.35}}};
    for (const Place& p : chairs) {
        b.set_placement({p.x, 0, p.z}, p.yaw);
        b.add_box({-0.22, 0.43, -0.22}, {0.22, 0.47, 0.22}, cell, kDarkWood);
        add_legs(b, 0.21, 0.21, 0.04, 0.0, 0.43, cell, kDarkWood);
        for (double sx : {-1.0, 1.0})  // back posts continue the rear legs above the seat
            b.add_box({sx * 0.19 - 0.02, 0.47, -0.21}, {sx * 0.19 + 0.02, 0.95, -0.17}, cell,
                      kDarkWood, kBoxNoBottom);
        b.add_box({-0.17, 0.62, -0.205}, {0.17, 0.90, -0.185}, cell, kDarkWood);
    }
}

void add_lounge(MeshBuilder& b, double cell) {
    // Sofa against the left wall, facing +X (local +Z).
    b.set_placement({-kW2 + 0.46, 0, 0.3}, 0.5 * kPi);
    add_legs(b, 1.02, 0.42, 0.06, 0.0, 0.08, cell, kDarkWood);
    b.add_box({-1.05, 0.08, -0.45}, {1.05, 0.40, 0.45}, cell, kSofaFabric);
    b.add_box({-1.05, 0.40, -0.45}, {1.05, 0.88, -0.25}, cell, kSofaFabric, kBoxNoBottom);
    for (double s : {-1.0, 1.0}) {
        const double x0 = s < 0 ? -1.05 : 0.87, x1 = s < 0 ? -0.87 : 1.05;
        b.add_box({x0, 0.40, -0.25}, {x1, 0.64, 0.45}, cell, kSofaFabric, kBoxNoBottom);
        const double c0 = s < 0 ? -0.86 : 0.005, c1 = s < 0 ? -0.005 : 0.86;
        b.add_box({c0, 0.40, -0.24}, {c1, 0.52, 0.44}, cell, kCushion, kBoxNoBottom);
        b.add_box({c0, 0.52, -0.24}, {c1, 0.82, -0.10}, cell, kCushion, kBoxNoBottom);
    }
    b.add_box({0.55, 0.52, -0.09}, {0.80, 0.74, 0.05}, cell, kPillowOrange, kBoxNoBottom);

    // Rug and coffee table in front of the sofa.
    constexpr double kRug = 0.012;
    b.reset_placement();
    b.add_box({-2.2, 0.0, -0.75}, {-0.75, kRug, 1.35}, cell, kRugRed, kBoxNoBottom);
    b.set_placement({-1.5, kRug, 0.3});
    b.add_box({-0.3, 0.36, -0.55}, {0.3, 0.40, 0.55}, cell, kLightWood);
    add_legs(b, 0.28, 0.53, 0.05, 0.0, 0.36, cell, kLightWood);
    b.add_cylinder({0.05, 0.40, 0.25}, 0.05, 0.04, 0.20, cell, kPorcelain, false, true);
}

void add_bookshelf(MeshBuilder& b, double cell, int books_per_shelf) {
    b.set_placement({1.9, 0, -kD2 + 0.01 + 0.175});  // against the back wall, facing +Z
    for (double s : {-1.0, 1.0})
        b.add_box({s < 0 ? -0.70 : 0.68, 0.0, -0.175}, {s < 0 ? -0.68 : 0.70, 2.0, 0.175}, cell,
                  kWalnut, kBoxNoBottom);
    b.add_box({-0.68, 0.0, -0.175}, {0.68, 2.0, -0.165}, cell, kWalnut, kBoxNoBottom);
    // Plinth, four shelves and the top; books stand on the first five surfaces.
    constexpr std::array<double, 6> kBoardBottom = {0.0, 0.46, 0.86, 1.26, 1.66, 1.975};
    constexpr std::array<double, 6> kBoardTop = {0.08, 0.485, 0.885, 1.285, 1.685, 2.0};
    for (std::size_t i = 0; i < kBoardTop.size(); ++i)
        b.add_box({-0.68, kBoardBottom[i], -0.165}, {0.68, kBoardTop[i], 0.175}, cell, kWalnut,
                  i == 0 ? kBoxNoBottom : kBoxAll);

    SplitMix rng(0x5348505254u);  // fixed: the room is one scene, not a family
    for (std::size_t shelf = 0; shelf + 1 < kBoardTop.size(); ++shelf) {
        const double y0 = kBoardTop[shelf];
        const double max_height = std::min(0.30, kBoardBottom[shelf + 1] - y0 - 0.03);
        double x = -0.66 + rng.uniform(0.0, 0.10);
        for (int k = 0; k < books_per_shelf; ++k) {
            const double w = rng.uniform(0.022, 0.05), h = rng.uniform(0.17, max_height);
            const double d = rng.uniform(0.16, 0.24);
            const double gap = rng.uniform(0.0, 1.0) < 0.1 ? 0.06 : 0.002;
            const auto colour = kBookColours[static_cast<std::size_t>(
                rng.uniform(0.0, static_cast<double>(kBookColours.size()) - 1e-9))];
            if (x + w > 0.66) break;
            b.add_box({x, y0, -0.16}, {x + w, y0 + h, -0.16 + d}, cell, colour, kBoxNoBottom);
            x += w + gap;
        }
    }
}

void add_decor(MeshBuilder& b, double cell) {
    // Floor lamp in the back-left corner.
    b.set_placement({-2.55, 0, -2.05});
    b.add_cylinder({0, 0, 0}, 0.16, 0.16, 0.03, cell, kBlack, false, true);
    b.add_cylinder({0, 0.03, 0}, 0.014, 0.014, 1.37, cell, kMetal, false, false);
    b.add_cylinder({0, 1.33, 0}, 0.24, 0.15, 0.32, cell, kShade, true, true);

    // Potted plant in the front-right corner, beside the door.
    b.set_placement({2.45, 0, 2.0});
    b.add_cylinder({0, 0, 0}, 0.16, 0.21, 0.38, cell, kTerracotta, false, true);
    b.add_sphere({0, 0.68, 0}, 0.32, cell, kLeaves);
    b.add_sphere({0.10, 0.98, -0.05}, 0.20, cell, kLeaves);

    // Picture on the right wall (local +Z faces into the room, local x runs along the wall).
    b.set_placement({kW2, 0, -1.1}, -0.5 * kPi);
    b.add_box({-0.6, 1.1, 0.005}, {0.6, 1.8, 0.035}, cell, kWalnut, kBoxAll & ~kBoxNegZ);
    b.add_box({-0.53, 1.17, 0.035}, {0.53, 1.73, 0.042}, cell, kCanvas, kBoxAll & ~kBoxNegZ);
}

int books_per_shelf(std::size_t triangles) {
    return static_cast<int>(std::clamp<std::size_t>(triangles / 500, 5, 28));
}

void build_room(MeshBuilder& b, double h, bool ceiling, int books) {
    const Cells c{h, 1.5 * h, 2.0 * h};
    add_shell(b, ceiling, c);
    add_dining_set(b, c.furniture);
    add_lounge(b, c.furniture);
    add_bookshelf(b, c.furniture, books);
    add_decor(b, c.furniture);
    b.reset_placement();
}

std::size_t count_room(double h, bool ceiling, int books) {
    MeshBuilder b(true);
    build_room(b, h, ceiling, books);
    return b.triangle_count();
}

void check_options(const RoomOptions& o) {
    SHPRT_CHECK(o.triangles >= kRoomMinTriangles && o.triangles <= kRoomMaxTriangles,
                invalid_argument, "room: {} triangles requested; the range is [{}, {}]",
                o.triangles, kRoomMinTriangles, kRoomMaxTriangles);
}

}  // namespace

double room_cell_size(const RoomOptions& options) {
    check_options(options);
    const std::size_t target = options.triangles;
    const int books = books_per_shelf(target);
    // The count never grows with the cell size, so bisect (geometrically) for the pair of cell
    // sizes that bracket the target and keep whichever count is closer.
    double lo = 1e-4, hi = 4.0;
    if (count_room(hi, options.ceiling, books) >= target) return hi;
    for (int i = 0; i < 60; ++i) {
        const double mid = std::sqrt(lo * hi);
        (count_room(mid, options.ceiling, books) >= target ? lo : hi) = mid;
    }
    const std::size_t n_lo = count_room(lo, options.ceiling, books);
    const std::size_t n_hi = count_room(hi, options.ceiling, books);
    return n_lo - target <= target - n_hi ? lo : hi;
}

Mesh generate_room(const RoomOptions& options) {
    const double h = room_cell_size(options);
    MeshBuilder b;
    build_room(b, h, options.ceiling, books_per_shelf(options.triangles));
    Mesh room = b.take_mesh("builtin:room");
    make_uv_atlas(room);  // for per-texel transfer: copies of the vertices where charts meet
    return room;
}

}  // namespace shprt
