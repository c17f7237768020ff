// Writers for per-vertex shading results (`shprt shade -o OUT.csv|OUT.ply|OUT.npy|OUT.npz`). Every
// row or vertex is in the mesh's vertex order (input order). All files are written atomically
// (AtomicFile): on any error no output file is left. Every writer refuses a result with an
// infinite or NaN value (Error(invalid_argument) naming the file and the vertex) before it
// creates the file.
#pragma once

#include "shprt/scene/mesh.hpp"
#include "shprt/shade/shade.hpp"

#include <string>

namespace shprt {

enum class ShadeFormat { csv, ply, npy, npz };

// From the extension of `path` (.csv, .ply, .npy, .npz, case-insensitive); throws
// Error(invalid_argument) naming the path otherwise.
ShadeFormat shade_format_for_path(const std::string& path);

// CSV: a header row "x,y,z,E_r,E_g,E_b,L_r,L_g,L_b", then one row per vertex; numbers with 9
// significant digits (float32 round-trips).
void write_shade_csv(const std::string& path, const Mesh& mesh, const ShadeResult& result);

// NPY (numpy format 1.0): a little-endian float32 array of shape (V, 9), C order, with the same
// columns as the CSV.
void write_shade_npy(const std::string& path, const Mesh& mesh, const ShadeResult& result);

// NPZ (what numpy.savez writes: a ZIP archive, stored, of .npy files): named float32 arrays
// position, irradiance and radiance, each (V, 3); numpy.load(path)["irradiance"].
void write_shade_npz(const std::string& path, const Mesh& mesh, const ShadeResult& result);

// Writes `data` (row-major, little-endian float32) as a NumPy .npy file (format 1.0) of the given
// shape, through AtomicFile. Throws Error(invalid_argument) when the sizes disagree, Error(io).
void write_npy_f32(const std::string& path, const std::vector<std::size_t>& shape,
                   const std::vector<float>& data);

// Binary little-endian PLY through write_ply (scene/ply.hpp, the one PLY writer): vertices with
// float x, y, z, nx, ny, nz and uchar red, green, blue (the radiance L times `exposure`, filmic
// tone mapped and sRGB encoded exactly as PNG images are, shade/save_image.hpp), then float
// irradiance_r, _g, _b and radiance_r, _g, _b (E and L exactly, linear, without the exposure), then
// the triangles as "list uchar uint vertex_indices". Opens in MeshLab and Blender. Needs normals
// (Error(invalid_argument)).
void write_shade_ply(const std::string& path, const Mesh& mesh, const ShadeResult& result,
                     float exposure = 1.0f);

// Dispatches on the extension (above).
void write_shade(const std::string& path, const Mesh& mesh, const ShadeResult& result,
                 float exposure = 1.0f);

}  // namespace shprt
