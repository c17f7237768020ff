// `shprt scene`: generate a built-in scene as PLY (`shprt scene room -o room.ply --triangles N
// --ceiling`), list the built-ins (`shprt scene list`), load any scene and describe it
// (`shprt scene info SPEC`), or give it a new UV atlas (`shprt scene unwrap SPEC -o OUT.ply`).
#include "common/command.hpp"
#include "common/option_table.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/io/shprt_file.hpp"
#include "shprt/scene/builtin.hpp"
#include "shprt/scene/load.hpp"
#include "shprt/scene/mesh_ops.hpp"
#include "shprt/scene/ply.hpp"
#include "shprt/scene/room.hpp"
#include "shprt/scene/uv_atlas.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace shprt::tools {
namespace {

struct GenerateArgs {
    std::string name;
    std::string output;
    std::size_t triangles = RoomOptions{}.triangles;
    bool ceiling = false;
};

void print(const std::string& text) { std::fwrite(text.data(), 1, text.size(), stdout); }

void generate(const GenerateArgs& args) {
    SHPRT_CHECK(lower_extension(args.output) == ".ply", invalid_argument,
                "{}: scenes are written as PLY (use a .ply name)", args.output);
    Mesh mesh;
    std::string detail;
    if (args.name == "room") {
        const RoomOptions options{args.triangles, args.ceiling};
        mesh = generate_room(options);
        detail = fmt::format(" ({} triangles requested, grid cells up to {:.3g} m{})",
                             args.triangles, room_cell_size(options),
                             args.ceiling ? ", ceiling with skylights" : ", open top");
    } else {
        mesh = make_builtin(args.name);
    }
    write_ply(mesh, args.output);
    print(
        fmt::format("wrote {}: builtin:{}{}\n{}", args.output, args.name, detail, describe(mesh)));
}

struct UnwrapArgs {
    std::string scene, output;
    UnwrapChoice atlas;  // scene/uv_atlas.hpp
};

// `shprt scene unwrap`: a conformal atlas (scene/uv_atlas.hpp) written as the PLY's s, t.
void unwrap(const UnwrapArgs& args) {
    SHPRT_CHECK(lower_extension(args.output) == ".ply", invalid_argument,
                "{}: scenes are written as PLY (use a .ply name)", args.output);
    const UvAtlasOptions options = unwrap_options_from(args.atlas);
    check_output_is_not_input(args.output, {args.scene});
    check_output_writable(args.output);
    Mesh mesh = load_scene(args.scene);
    const UvAtlasInfo info = make_uv_atlas(mesh, options);
    write_ply(mesh, args.output);
    print(fmt::format("wrote {}: {} with a new UV atlas\nunwrap: {}\n{}", args.output, args.scene,
                      describe(info), describe(mesh)));
}

const bool scene_registered = register_command(
    {"scene", "Generate a built-in scene as PLY, list the built-ins, or describe a scene", 20,
     [](CLI::App& app) {
         app.require_subcommand(1);

         app.add_subcommand("list", "List the built-in scenes (usable as builtin:NAME)")
             ->callback([] {
                 for (const std::string& name : builtin_scene_names())
                     print(fmt::format("{:<13} {}\n", name, builtin_scene_summary(name)));
             });

         auto spec = std::make_shared<std::string>();
         CLI::App* info = app.add_subcommand(
             "info", "Load a scene (a mesh file or builtin:NAME) and print its size and bounds");
         info->add_option("scene", *spec, "Scene file (OBJ, PLY, glTF, FBX, ...) or builtin:NAME")
             ->required();
         info->callback([spec] {
             const Mesh mesh = load_scene(*spec);
             print(fmt::format("{}\n{}", *spec, describe(mesh)));
         });

         // The mesh a bake stored (a refined one, after `shprt bake --refine`) as PLY.
         auto mesh_args = std::make_shared<GenerateArgs>();
         CLI::App* from_file = app.add_subcommand(
             "mesh",
             "Write the mesh of a .shprt file (the refined mesh of a --refine bake) as PLY");
         from_file->add_option("file", mesh_args->name, "Baked .shprt file")->required();
         from_file->add_option("-o,--output", mesh_args->output, "Output PLY file")->required();
         from_file->callback([mesh_args] {
             SHPRT_CHECK(lower_extension(mesh_args->output) == ".ply", invalid_argument,
                         "{}: scenes are written as PLY (use a .ply name)", mesh_args->output);
             check_output_is_not_input(mesh_args->output, {mesh_args->name});
             check_output_writable(mesh_args->output);
             const ShprtFile file = read_shprt(mesh_args->name);
             write_ply(file.mesh, mesh_args->output);
             print(fmt::format("wrote {}: the mesh of {}\n{}", mesh_args->output, mesh_args->name,
                               describe(file.mesh)));
         });

         auto unwrap_args = std::make_shared<UnwrapArgs>();
         CLI::App* un = app.add_subcommand(
             "unwrap",
             "Give a scene a new UV atlas (conformal charts, packed with gutters) and write it as "
             "PLY, for `bake --domain texel`");
         un->add_option("scene", unwrap_args->scene,
                        "Scene file (OBJ, PLY, glTF, ...) or builtin:NAME")
             ->required();
         un->add_option("-o,--output", unwrap_args->output, "Output PLY file")->required();
         add_table_options(*un, unwrap_option_table(), unwrap_args->atlas);
         un->callback([unwrap_args] { unwrap(*unwrap_args); });

         for (const std::string& name : builtin_scene_names()) {
             auto args = std::make_shared<GenerateArgs>();
             args->name = name;
             CLI::App* sub = app.add_subcommand(name, builtin_scene_summary(name));
             sub->add_option("-o,--output", args->output, "Output PLY file (written atomically)")
                 ->required();
             if (name == "room") {
                 sub->add_option("--triangles", args->triangles,
                                 fmt::format("Approximate triangle count, {} to {}",
                                             kRoomMinTriangles, kRoomMaxTriangles))
                     ->capture_default_str();
                 sub->add_flag("--ceiling", args->ceiling,
                               "Close the top with a ceiling that has two skylights");
             }
             sub->callback([args] { generate(*args); });
         }
     }});

}  // namespace
}  // namespace shprt::tools
