// The bake request's option tables (bake/request_options.hpp).
#include "shprt/bake/request_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"

#include <fmt/format.h>

namespace shprt {

const std::vector<OptionRow<ReceiverChoice>>& receiver_option_table() {
    static const std::vector<OptionRow<ReceiverChoice>> table = [] {
        using C = ReceiverChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "domain", &C::domain,
                "Receivers: vertex (default) or texel (the texel centres of the scene's UV "
                "atlas; needs --resolution, or --unwrap --texel-density)");
        add_row(t, "resolution", &C::resolution, "Texel domain: image size W or WxH");
        add_row(t, "unwrap", &C::unwrap,
                "Texel domain: make a new UV atlas (conformal charts, packed with gutters) "
                "instead of the scene's UVs; the file keeps the unwrapped mesh");
        add_row(t, "texel_density", &C::texel_density,
                "Texel domain with --unwrap: texels per metre (chooses the resolution)");
        add_row(t, "uv_set", &C::uv_set, "Texel domain: which UV set of the scene (default 0)");
        add_row(t, "float32", &C::float32,
                "Texel domain: store float32 coefficients (default float16)");
        add_row(t, "refine", &C::refine,
                "Adaptive refinement: split edges whose ends' irradiance under 14 test lights "
                "differs by more than this fraction of full brightness (e.g. 0.05)");
        add_row(t, "max_vertices", &C::max_vertices,
                "Refinement: stop at this many vertices (default 16x the scene's)");
        add_row(t, "max_edge_split_depth", &C::max_edge_split_depth,
                "Refinement: how many times an edge may be halved (1 to 30, default 6)");
        add_row(t, "probes", &C::probes,
                "Transfer probes beside the receivers, for objects that move: auto (every "
                "0.5 m over the scene's bounds), auto:SPACING, NX,NY,NZ or NX,NY,NZ:SPACING");
        add_row(t, "probe_box", &C::probe_box,
                "Probes: the grid's box X0,Y0,Z0,X1,Y1,Z1 (default: the scene's bounds)");
        add_row(t, "probe_bands", &C::probe_bands,
                "Probes: SH bands of their matrices (1 to 8, default 3: 9x9)");
        add_row(t, "shard", &C::shard,
                "Bake part I of N (I/N, 0-based) of the vertices, for job arrays; join the "
                "parts with `shprt merge`");
        return complete_rows(std::move(t));
    }();
    return table;
}

const std::vector<OptionRow<FileChoice>>& file_option_table() {
    static const std::vector<OptionRow<FileChoice>> table = [] {
        using C = FileChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "half", &C::half, "Store coefficients as float16");
        add_row(t, "stream", &C::stream,
                "Write coefficients to the file as chunks finish (no V×K array in memory)");
        add_row(t, "reproducible", &C::reproducible,
                "Leave out what differs between runs (times, rays, peak memory, device, "
                "the command line), so that the same bake gives the same bytes");
        return complete_rows(std::move(t));
    }();
    return table;
}

FileOutput file_output_from(std::string path, const FileChoice& choice, bool float32) {
    FileOutput file;
    file.path = std::move(path);
    file.stream = choice.stream;
    if (choice.half) file.encoding = TransferEncoding::f16;
    if (float32) file.encoding = TransferEncoding::f32;
    file.write.reproducible = choice.reproducible;
    return file;
}

const std::vector<OptionRow<CheckpointChoice>>& checkpoint_option_table() {
    static const std::vector<OptionRow<CheckpointChoice>> table = [] {
        using C = CheckpointChoice;
        std::vector<OptionRow<C>> t;
        add_row(t, "checkpoint", &C::checkpoint,
                "Keep the finished rows in this file as the bake goes, so that a killed bake can "
                "continue with --resume (removed when the output is written)");
        add_row(t, "resume", &C::resume,
                "Continue the bake whose checkpoint is this file (same scene and options): the "
                "result is the uninterrupted bake's, bit for bit");
        add_row(t, "checkpoint_every", &C::checkpoint_every,
                "Seconds between syncs of the checkpoint to disk (default 30; every finished "
                "chunk is written at once, which a killed process does not lose)");
        add_row(t, "max_memory", &C::max_memory,
                "Refuse the bake when its estimated peak memory exceeds this size (512M, "
                "4G, ...; default: the memory the machine has available)");
        return complete_rows(std::move(t));
    }();
    return table;
}

void apply_max_memory(const std::string& text, BakeRequest& request, Spelling spelling) {
    if (text.empty()) return;
    SHPRT_CHECK(parse_byte_size(text, request.max_memory) && request.max_memory > 0,
                invalid_argument, "{}: expected a size such as 512M or 4G (bytes, K, M, G or T)",
                option_text(spelling, "max_memory", "'" + text + "'"));
}

void apply_checkpoint_choice(const CheckpointChoice& c, BakeRequest& request, Spelling spelling) {
    apply_max_memory(c.max_memory, request, spelling);
    const bool resume = !c.resume.empty();
    if (c.checkpoint.empty() && !resume) return;
    request.checkpoint =
        CheckpointRequest{resume ? c.resume : c.checkpoint, resume, c.checkpoint_every};
}

std::string resume_hint(const CheckpointKept& kept, const char* signal) {
    if (signal)
        return fmt::format(
            "interrupted by {}; {} of {} receivers are saved in {}: to continue, run the same "
            "command with --resume {} in place of --checkpoint (no output was written)",
            signal, kept.done, kept.count, kept.path, kept.path);
    return fmt::format(
        "{}: to continue once that is fixed, run the same command with --resume {} in place of "
        "--checkpoint (no output was written)",
        kept.what(), kept.path);
}

}  // namespace shprt
