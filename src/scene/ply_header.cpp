// PLY header checks (Turk, "The PLY polygon file format", 1994): see ply_header.hpp.
#include "ply_header.hpp"

#include "shprt/core/error.hpp"

#include <cctype>
#include <sstream>
#include <vector>

namespace shprt::detail {
namespace {

// Bytes of a scalar PLY type; 0 for an unknown type name.
std::size_t type_size(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

bool is_identifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
            return false;
    return true;
}

// A header line as it may appear in a one-line message: printable ASCII, at most 60 characters.
std::string printable(const std::string& line) {
    std::string r;
    for (char c : line.substr(0, 60)) r += (c >= 0x20 && c < 0x7f) ? c : '?';
    return line.size() > 60 ? r + "..." : r;
}

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::size_t properties = 0;
    std::size_t min_binary_bytes = 0;  // scalars, plus the count of each (possibly empty) list
    bool x = false, y = false, z = false;
};

}  // namespace

bool looks_like_ply(const std::string& prefix) {
    return prefix.size() >= 4 &&
           (prefix.compare(0, 3, "ply") == 0 || prefix.compare(0, 3, "PLY") == 0) &&
           (prefix[3] == '\n' || prefix[3] == '\r');
}

PlyHeader check_ply_header(const std::string& path, const std::string& prefix,
                           std::uintmax_t file_size) {
    SHPRT_CHECK(looks_like_ply(prefix), format, "{}: not a PLY file (no 'ply' first line)", path);
    PlyHeader header;
    std::vector<Element> elements;
    std::string format;
    std::size_t pos = prefix.find('\n') + 1, header_bytes = 0;
    int line_number = 1;
    while (pos < prefix.size()) {
        const std::size_t end = prefix.find('\n', pos);
        if (end == std::string::npos) break;  // cut off by the end of the file or the prefix
        std::string line = prefix.substr(pos, end - pos);
        pos = end + 1;
        ++line_number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "comment" || keyword == "obj_info" || keyword.empty()) continue;
        if (keyword == "end_header") {
            std::string extra;
            SHPRT_CHECK(!(words >> extra), format, "{}: PLY header line {}: text after end_header",
                        path, line_number);
            header_bytes = pos;
            break;
        }
        if (keyword == "format") {
            words >> format;
            SHPRT_CHECK(format == "ascii" || format == "binary_little_endian" ||
                            format == "binary_big_endian",
                        format, "{}: PLY header line {}: unknown format '{}'", path, line_number,
                        printable(format));
            continue;
        }
        if (keyword == "element") {
            Element e;
            std::string count;
            words >> e.name >> count;
            SHPRT_CHECK(is_identifier(e.name) && !count.empty() && count.size() <= 19 &&
                            count.find_first_not_of("0123456789") == std::string::npos,
                        format, "{}: PLY header line {}: bad element line '{}'", path, line_number,
                        printable(line));
            e.count = std::stoull(count);
            elements.push_back(e);
            continue;
        }
        if (keyword == "property") {
            SHPRT_CHECK(!elements.empty(), format,
                        "{}: PLY header line {}: property before any element", path, line_number);
            Element& e = elements.back();
            std::string type, name;
            words >> type;
            if (type == "list") {
                std::string count_type, item_type;
                words >> count_type >> item_type >> name;
                SHPRT_CHECK(
                    type_size(count_type) > 0 && type_size(item_type) > 0 && is_identifier(name),
                    format, "{}: PLY header line {}: bad list property '{}'", path, line_number,
                    printable(line));
                e.min_binary_bytes += type_size(count_type);
            } else {
                words >> name;
                SHPRT_CHECK(type_size(type) > 0 && is_identifier(name), format,
                            "{}: PLY header line {}: bad property '{}'", path, line_number,
                            printable(line));
                e.min_binary_bytes += type_size(type);
            }
            ++e.properties;
            if (e.name == "vertex") {
                e.x = e.x || name == "x";
                e.y = e.y || name == "y";
                e.z = e.z || name == "z";
                if (name == "red" || name == "r" || name == "diffuse_red")
                    header.colours_8bit = type_size(type) == 1;
            }
            continue;
        }
        // No keyword: Assimp passes over such a line, and so does this check (the loader warns).
        // A line that begins like end_header is not passed over: Assimp never returns on one.
        SHPRT_CHECK(keyword.rfind("end_header", 0) != 0, format,
                    "{}: PLY header line {}: unexpected '{}'", path, line_number, printable(line));
        if (header.unknown_lines++ == 0) {
            header.first_unknown_line = line_number;
            header.first_unknown = printable(line);
        }
    }
    SHPRT_CHECK(header_bytes > 0, format,
                "{}: truncated or invalid PLY header (no end_header line in the first {} bytes)",
                path, kMaxPlyHeader);
    SHPRT_CHECK(!format.empty(), format, "{}: PLY header has no format line", path);

    // Every element needs some bytes: its binary scalars, or in ASCII a character and a separator
    // per value. A header declaring more than the file holds is truncated or corrupt.
    const bool ascii = format == "ascii";
    const std::uintmax_t body = file_size - header_bytes;
    long double needed = 0.0L;
    bool has_vertex = false;
    for (const Element& e : elements) {
        const std::size_t per = ascii ? 2 * e.properties : e.min_binary_bytes;
        needed += static_cast<long double>(e.count) * static_cast<long double>(per);
        if (e.name == "vertex") {
            SHPRT_CHECK(e.x && e.y && e.z, format, "{}: PLY vertex element lacks x, y or z", path);
            header.vertices = e.count;
            has_vertex = true;
        }
        header.has_material = header.has_material || e.name == "material";
    }
    SHPRT_CHECK(has_vertex, format, "{}: PLY file has no vertex element", path);
    // The last ASCII value needs no separator after it.
    if (ascii && needed > 0.0L) needed -= 1.0L;
    SHPRT_CHECK(needed <= static_cast<long double>(body), format,
                "{}: the PLY header declares more data than the {} bytes after it hold "
                "(truncated or corrupt file)",
                path, body);
    return header;
}

void check_off_header(const std::string& path, const std::string& prefix,
                      std::uintmax_t file_size) {
    std::istringstream in(prefix);
    std::string line, token;
    // The first line that is not a comment or blank holds the header token.
    while (std::getline(in, line)) {
        const auto first = line.find_first_not_of(" \t\r");
        if (first != std::string::npos && line[first] != '#') break;
    }
    std::istringstream head(line);
    if (!(head >> token) || (token != "OFF" && token != "COFF" && token != "NOFF")) return;
    // The counts follow on the same line or on the next line that is not a comment.
    std::string counts;
    std::getline(head, counts);
    if (counts.find_first_not_of(" \t\r") == std::string::npos) {
        while (std::getline(in, line)) {
            const auto first = line.find_first_not_of(" \t\r");
            if (first != std::string::npos && line[first] != '#') break;
        }
        counts = line;
    }
    std::istringstream numbers(counts);
    std::uint64_t vertices = 0, faces = 0;
    if (!(numbers >> vertices >> faces)) return;
    SHPRT_CHECK(vertices <= file_size / 6 && faces <= file_size / 8, format,
                "{}: the OFF header claims {} vertices and {} faces, more than a file of {} bytes "
                "can hold",
                path, vertices, faces, file_size);
}

}  // namespace shprt::detail
