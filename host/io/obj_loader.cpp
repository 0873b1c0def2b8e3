#include "io/obj_loader.hpp"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"

namespace swarmcl {
namespace {

[[noreturn]] void parse_error(const std::string& name, size_t line, const std::string& what) {
    fail(Status::Parse, name + ":" + std::to_string(line) + ": " + what);
}

// tinyobjloader accepts NaN coordinates and leaves out-of-range indices to
// the caller without telling the line, so one pass over the text checks what
// needs a line number: every "v" has three finite numbers, every "f" index
// (the part before '/') is a non-zero integer that names an existing vertex
// (negative: relative to the vertices read so far, as OBJ defines).
void check_lines(const std::string& text, const std::string& name) {
    struct Face {
        size_t line;
        long index;
    };
    std::vector<Face> faces;  // positive indices, checked once every vertex is counted
    size_t vertices = 0, line_no = 0, pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        std::istringstream in(line);
        std::string tag;
        if (!(in >> tag)) continue;
        if (tag == "v") {
            for (int k = 0; k < 3; ++k) {
                std::string tok;
                if (!(in >> tok)) parse_error(name, line_no, "vertex has fewer than 3 coordinates");
                errno = 0;
                char* stop = nullptr;
                const double v = std::strtod(tok.c_str(), &stop);
                if (stop == tok.c_str() || *stop != '\0')
                    parse_error(name, line_no, "vertex coordinate '" + tok + "' is not a number");
                if (!std::isfinite(v) || !std::isfinite(float(v)))
                    parse_error(name, line_no, "vertex coordinate '" + tok + "' is NaN or infinite");
            }
            ++vertices;
        } else if (tag == "f") {
            std::string tok;
            int corners = 0;
            while (in >> tok) {
                const std::string head = tok.substr(0, tok.find('/'));
                char* stop = nullptr;
                errno = 0;
                const long idx = std::strtol(head.c_str(), &stop, 10);
                if (head.empty() || *stop != '\0' || errno == ERANGE)
                    parse_error(name, line_no, "face index '" + tok + "' is not an integer");
                if (idx == 0) parse_error(name, line_no, "face index 0 (OBJ indices start at 1)");
                // -(idx + 1) + 1: -idx overflows for LONG_MIN (fuzzing finding).
                if (idx < 0 && size_t(-(idx + 1)) + 1 > vertices)
                    parse_error(name, line_no, "face index " + std::to_string(idx) + " reaches before the first vertex");
                if (idx > 0) faces.push_back({line_no, idx});
                ++corners;
            }
            if (corners < 3) parse_error(name, line_no, "face has fewer than 3 corners");
        }
    }
    for (const Face& f : faces)
        if (size_t(f.index) > vertices)
            parse_error(name, f.line, "face index " + std::to_string(f.index) + " is out of range (the file has " +
                                          std::to_string(vertices) + " vertices)");
}

}  // namespace

TriangleMesh parse_obj(const std::string& text, const std::string& name, size_t* skipped) {
    check_lines(text, name);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(text, "", config) || !reader.Error().empty())
        fail(Status::Parse, name + ": " + (reader.Error().empty() ? "not a valid OBJ file" : reader.Error()));
    const auto& attrib = reader.GetAttrib();
    std::vector<float> xyz(attrib.vertices.begin(), attrib.vertices.end());
    std::vector<uint32_t> indices;
    for (const auto& shape : reader.GetShapes())
        for (const auto& idx : shape.mesh.indices) {
            if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= attrib.vertices.size() / 3)
                fail(Status::Parse, name + ": face index out of range");
            indices.push_back(uint32_t(idx.vertex_index));
        }
    if (indices.empty()) fail(Status::Parse, name + ": no faces (an obstacle mesh needs triangles)");
    if (indices.size() % 3 != 0) fail(Status::Parse, name + ": faces did not triangulate");
    try {
        return make_mesh(xyz.data(), xyz.size() / 3, indices.data(), indices.size() / 3, skipped);
    } catch (const Error& e) {
        throw Error(e.status(), name + ": " + e.what());
    }
}

TriangleMesh load_obj(const std::string& path, size_t* skipped) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(Status::Io, "cannot open OBJ file '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) fail(Status::Io, "cannot read OBJ file '" + path + "'");
    return parse_obj(text.str(), path, skipped);
}

}  // namespace swarmcl
