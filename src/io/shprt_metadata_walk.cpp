// The walks over the metadata field table (shprt_metadata.hpp): the writer's, in key order, and
// the reader's, pass by pass.
#include "io/shprt_metadata.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

namespace shprt::detail {
namespace {

// Adds `extra` into `target`: objects merge recursively, any other collision is an error (the
// writer's own fields must stay what the reader expects).
void merge_extra(Json& target, const Json& extra, const std::string& where) {
    for (auto it = extra.begin(); it != extra.end(); ++it) {
        const std::string key = where.empty() ? it.key() : where + "." + it.key();
        if (!target.contains(it.key())) {
            target[it.key()] = it.value();
        } else if (target[it.key()].is_object() && it.value().is_object()) {
            merge_extra(target[it.key()], it.value(), key);
        } else {
            fail(ErrorCode::invalid_argument,
                 "extra metadata key '{}' would replace a value the writer sets", key);
        }
    }
}

// The row of the object holding `rule` (null at the root).
const FieldRule* parent_of(const FieldRule& rule) {
    const std::string_view key = rule.key;
    const std::size_t dot = key.rfind('.');
    if (dot == std::string_view::npos) return nullptr;
    for (const FieldRule& r : field_rules())
        if (key.substr(0, dot) == r.key) return &r;
    return nullptr;
}

const char* leaf_of(const FieldRule& rule) {
    const char* dot = std::strrchr(rule.key, '.');
    return dot ? dot + 1 : rule.key;
}

bool is_written(const FieldRule& rule, const MetaSource& s) {
    const FieldRule* parent = parent_of(rule);
    // Only the rows of the file's version (a CPCA code's make it 3: file_version), the parent
    // first: a row's own test may look into its parent's part (s.probes, s.cpca).
    return rule.since <= file_version(s.sections) && (!parent || is_written(*parent, s)) &&
           (!rule.written || rule.written(s));
}

// The object that holds `rule` in the file (nullopt: absent and optional, or not read in a file
// of that version); a required object that is absent is the "missing field" error.
std::optional<Fields> parent_fields(const FieldRule& rule, const Fields& root,
                                    const MetaTarget& t) {
    const FieldRule* parent = parent_of(rule);
    if (!parent) return root;
    const std::optional<Fields> above = parent_fields(*parent, root, t);
    if (!above || parent->since > t.version) return std::nullopt;
    const char* leaf = leaf_of(*parent);
    if (!parent->required && !above->obj.contains(leaf)) return std::nullopt;
    return above->object(leaf);
}

// Whether `value` is of the JSON type the row states (checked in debug builds, as written).
[[maybe_unused]] bool has_type(FieldType type, const Json& value) {
    switch (type) {
        case FieldType::text:
            return value.is_string();
        case FieldType::whole:
            return value.is_number_integer();
        case FieldType::number:
            return value.is_number();
        case FieldType::boolean:
            return value.is_boolean();
        case FieldType::list:
            return value.is_array();
        case FieldType::object:
            return value.is_object();
        case FieldType::extra:
            break;
    }
    return false;
}

}  // namespace

Json write_metadata(const MetaSource& s) {
    Json m;
    for (const FieldRule& rule : field_rules()) {
        if (!is_written(rule, s)) continue;
        if (rule.type == FieldType::extra) {
            const bool kept = std::string_view(rule.key) == kKeptMetadata;
            merge_extra(m, kept ? parse_extra(s.options.kept_metadata_json) : s.extra, "");
        } else if (rule.value) {
            std::string pointer = std::string("/") + rule.key;
            std::replace(pointer.begin(), pointer.end(), '.', '/');
            Json& field = m[Json::json_pointer(pointer)];
            field = rule.value(s);
            SHPRT_DCHECK(has_type(rule.type, field));
        }
    }
    return m;
}

void read_metadata(const Fields& metadata, MetaTarget& t) {
    // A field of a newer version than the file's is refused, not ignored ('cpca' in a version 2
    // file: the rows would be read as if there were no code).
    for (const FieldRule& rule : field_rules())
        if (rule.since > t.version && !parent_of(rule) && metadata.obj.contains(rule.key))
            corrupt(t.path, "metadata: '{}' in a version {} file (it came with version {})",
                    rule.key, t.version, rule.since);
    for (int pass = 1; pass <= 3; ++pass)
        for (const FieldRule& rule : field_rules()) {
            if (rule.pass != pass || !rule.read || rule.since > t.version) continue;
            const std::optional<Fields> parent = parent_fields(rule, metadata, t);
            if (!parent) continue;
            const char* leaf = leaf_of(rule);
            if (rule.with && !parent->obj.contains(rule.with)) continue;
            if (!rule.required && !parent->obj.contains(leaf)) continue;
            rule.read(*parent, leaf, t);
        }
}

}  // namespace shprt::detail
