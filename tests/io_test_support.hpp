// Helpers shared by the file tests (test_io, test_scenario, test_cli): a
// temporary folder removed at the end, reading files, listing folders, and
// readers for the formats the recorder writes (CSV, .npy, .vtp, .pvd) that
// follow the formats' own rules rather than the writer's code.
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace swarmcl::iotest {

namespace fs = std::filesystem;

// A fresh folder under the system temp folder, removed with its contents.
class TempDir {
public:
    TempDir() {
        std::string pattern = (fs::temp_directory_path() / "swarmcl-io-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
        path_ = pattern;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }
    std::string operator/(const std::string& name) const { return path_ + "/" + name; }

private:
    std::string path_;
};

inline std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

// Names of the entries in a folder (not recursive), sorted.
inline std::set<std::string> list_dir(const std::string& dir) {
    std::set<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) names.insert(e.path().filename().string());
    return names;
}

// A CSV row of the trajectory format.
struct CsvRow {
    uint32_t id, frame;
    float p[3], v[3];
};

// Parses `id,frame,P.x,P.y,P.z,v.x,v.y,v.z`; fails the test on anything else.
inline std::vector<CsvRow> parse_trajectory_csv(const std::string& text) {
    std::vector<CsvRow> rows;
    std::istringstream in(text);
    std::string line;
    if (!std::getline(in, line)) {
        ADD_FAILURE() << "empty CSV";
        return rows;
    }
    EXPECT_EQ(line, "id,frame,P.x,P.y,P.z,v.x,v.y,v.z");
    size_t line_no = 1;
    while (std::getline(in, line)) {
        ++line_no;
        std::vector<std::string> cells;
        std::stringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ',')) cells.push_back(cell);
        if (cells.size() != 8) {
            ADD_FAILURE() << "CSV line " << line_no << " has " << cells.size() << " cells: " << line;
            continue;
        }
        CsvRow r{};
        char* end = nullptr;
        r.id = uint32_t(std::strtoul(cells[0].c_str(), &end, 10));
        EXPECT_EQ(*end, '\0') << line;
        r.frame = uint32_t(std::strtoul(cells[1].c_str(), &end, 10));
        EXPECT_EQ(*end, '\0') << line;
        for (int a = 0; a < 3; ++a) {
            r.p[a] = std::strtof(cells[2 + a].c_str(), &end);
            EXPECT_EQ(*end, '\0') << line;
            r.v[a] = std::strtof(cells[5 + a].c_str(), &end);
            EXPECT_EQ(*end, '\0') << line;
        }
        rows.push_back(r);
    }
    return rows;
}

// A .npy file read by the format's rules (NEP 1 / numpy.lib.format):
// magic, version, little-endian header length, an ASCII dict ending in '\n',
// total header length a multiple of 64, then the raw data.
struct Npy {
    std::string descr;
    bool fortran_order = true;
    std::vector<uint64_t> shape;
    size_t header_bytes = 0;
    std::string data;  // raw bytes after the header
};

inline Npy read_npy(const std::string& path) {
    Npy npy;
    const std::string bytes = read_bytes(path);
    EXPECT_GE(bytes.size(), 10u) << path;
    if (bytes.size() < 10) return npy;
    EXPECT_EQ(bytes.substr(0, 6), std::string("\x93NUMPY", 6)) << path;
    const int major = (unsigned char)bytes[6], minor = (unsigned char)bytes[7];
    size_t len = 0, prefix = 0;
    if (major == 1) {
        len = (unsigned char)bytes[8] | (size_t((unsigned char)bytes[9]) << 8);
        prefix = 10;
    } else {
        EXPECT_TRUE(major == 2 || major == 3) << "npy version " << major;
        len = 0;
        for (int i = 0; i < 4; ++i) len |= size_t((unsigned char)bytes[8 + i]) << (8 * i);
        prefix = 12;
    }
    EXPECT_EQ(minor, 0);
    npy.header_bytes = prefix + len;
    // numpy.lib.format: "the total of len(magic string) + 2 + len(length) +
    // HEADER_LEN is evenly divisible by 64 for alignment purposes".
    EXPECT_EQ(npy.header_bytes % 64, 0u) << path;
    EXPECT_LE(npy.header_bytes, bytes.size()) << path;
    if (npy.header_bytes > bytes.size()) return npy;
    const std::string dict = bytes.substr(prefix, len);
    EXPECT_FALSE(dict.empty());
    if (dict.empty()) return npy;
    EXPECT_EQ(dict.back(), '\n') << "the header ends with a newline";
    for (char c : dict) EXPECT_TRUE(c >= 0x20 || c == '\n') << "non-printable byte in the header";
    auto value_of = [&](const std::string& key) -> std::string {
        const std::string k = "'" + key + "':";
        const size_t at = dict.find(k);
        EXPECT_NE(at, std::string::npos) << "no " << key << " in " << dict;
        if (at == std::string::npos) return {};
        size_t b = at + k.size();
        while (b < dict.size() && dict[b] == ' ') ++b;
        return dict.substr(b);
    };
    {
        const std::string v = value_of("descr");
        if (!v.empty() && v[0] == '\'') npy.descr = v.substr(1, v.find('\'', 1) - 1);
    }
    {
        const std::string v = value_of("fortran_order");
        npy.fortran_order = v.rfind("True", 0) == 0;
        EXPECT_TRUE(v.rfind("True", 0) == 0 || v.rfind("False", 0) == 0) << v;
    }
    {
        const std::string v = value_of("shape");
        EXPECT_FALSE(v.empty());
        if (!v.empty() && v[0] == '(') {
            const std::string inner = v.substr(1, v.find(')') - 1);
            std::stringstream s(inner);
            std::string item;
            while (std::getline(s, item, ',')) {
                if (item.find_first_not_of(' ') == std::string::npos) continue;
                npy.shape.push_back(std::strtoull(item.c_str(), nullptr, 10));
            }
        }
    }
    npy.data = bytes.substr(npy.header_bytes);
    return npy;
}

// A DataArray of a VTK XML file with raw appended data.
struct VtpArray {
    std::string type, name;
    int components = 1;
    uint64_t offset = 0;
    std::string bytes;  // the block's payload
};

struct Vtp {
    std::string xml;  // everything before the appended data
    uint64_t points = 0, verts = 0;
    std::map<std::string, VtpArray> arrays;  // by Name ("Points" for the points)
};

inline std::string xml_attr(const std::string& tag, const std::string& name) {
    const std::string k = " " + name + "=\"";
    const size_t at = tag.find(k);
    if (at == std::string::npos) return {};
    const size_t b = at + k.size();
    return tag.substr(b, tag.find('"', b) - b);
}

// Reads a .vtp with `header_type="UInt64"` raw appended blocks: each array's
// offset counts from the byte after the '_' that starts the appended data,
// and each block is a UInt64 byte count followed by that many bytes.
inline Vtp read_vtp(const std::string& path) {
    Vtp vtp;
    const std::string bytes = read_bytes(path);
    const std::string start = "<AppendedData encoding=\"raw\">";
    const size_t app = bytes.find(start);
    EXPECT_NE(app, std::string::npos) << path;
    if (app == std::string::npos) return vtp;
    size_t underscore = bytes.find('_', app + start.size());
    EXPECT_NE(underscore, std::string::npos);
    for (size_t i = app + start.size(); i < underscore; ++i) EXPECT_TRUE(std::isspace((unsigned char)bytes[i]));
    const size_t base = underscore + 1;
    vtp.xml = bytes.substr(0, app);
    EXPECT_NE(vtp.xml.find("type=\"PolyData\""), std::string::npos);
    EXPECT_NE(vtp.xml.find("byte_order=\"LittleEndian\""), std::string::npos);
    EXPECT_NE(vtp.xml.find("header_type=\"UInt64\""), std::string::npos);
    const size_t piece = vtp.xml.find("<Piece ");
    EXPECT_NE(piece, std::string::npos);
    if (piece != std::string::npos) {
        const std::string tag = vtp.xml.substr(piece, vtp.xml.find('>', piece) - piece);
        vtp.points = std::strtoull(xml_attr(tag, "NumberOfPoints").c_str(), nullptr, 10);
        vtp.verts = std::strtoull(xml_attr(tag, "NumberOfVerts").c_str(), nullptr, 10);
    }
    uint64_t end_of_blocks = 0;
    for (size_t at = vtp.xml.find("<DataArray"); at != std::string::npos; at = vtp.xml.find("<DataArray", at + 1)) {
        const std::string tag = vtp.xml.substr(at, vtp.xml.find('>', at) - at);
        VtpArray a;
        a.type = xml_attr(tag, "type");
        a.name = xml_attr(tag, "Name");
        const std::string comps = xml_attr(tag, "NumberOfComponents");
        a.components = comps.empty() ? 1 : std::atoi(comps.c_str());
        EXPECT_EQ(xml_attr(tag, "format"), "appended") << tag;
        a.offset = std::strtoull(xml_attr(tag, "offset").c_str(), nullptr, 10);
        if (a.name.empty()) {
            // The unnamed array inside <Points>.
            const size_t points = vtp.xml.rfind("<Points>", at);
            EXPECT_TRUE(points != std::string::npos && vtp.xml.find("</Points>", points) > at) << tag;
            a.name = "Points";
        }
        EXPECT_LE(base + a.offset + 8, bytes.size()) << a.name;
        if (base + a.offset + 8 > bytes.size()) continue;
        uint64_t n = 0;
        std::memcpy(&n, bytes.data() + base + a.offset, 8);
        EXPECT_LE(base + a.offset + 8 + n, bytes.size()) << a.name;
        if (base + a.offset + 8 + n > bytes.size()) continue;
        a.bytes = bytes.substr(base + a.offset + 8, n);
        end_of_blocks = std::max<uint64_t>(end_of_blocks, a.offset + 8 + n);
        EXPECT_EQ(vtp.arrays.count(a.name), 0u) << "duplicate array " << a.name;
        vtp.arrays[a.name] = a;
    }
    // After the last block: the closing tags and nothing else.
    const std::string tail = bytes.substr(std::min<size_t>(bytes.size(), base + end_of_blocks));
    EXPECT_NE(tail.find("</AppendedData>"), std::string::npos);
    EXPECT_NE(tail.find("</VTKFile>"), std::string::npos);
    return vtp;
}

// (file, timestep) of each DataSet of a .pvd collection, in order.
inline std::vector<std::pair<std::string, double>> read_pvd(const std::string& path) {
    std::vector<std::pair<std::string, double>> out;
    const std::string xml = read_bytes(path);
    EXPECT_NE(xml.find("type=\"Collection\""), std::string::npos) << path;
    EXPECT_NE(xml.find("</VTKFile>"), std::string::npos) << path;
    for (size_t at = xml.find("<DataSet"); at != std::string::npos; at = xml.find("<DataSet", at + 1)) {
        const std::string tag = xml.substr(at, xml.find('>', at) - at);
        out.emplace_back(xml_attr(tag, "file"), std::strtod(xml_attr(tag, "timestep").c_str(), nullptr));
    }
    return out;
}

// (line, column) from "... line L, column C ..."; (0, 0) when absent.
inline std::pair<int, int> line_column(const std::string& msg) {
    const size_t at = msg.find("line ");
    if (at == std::string::npos) return {0, 0};
    int line = 0, col = 0;
    if (std::sscanf(msg.c_str() + at, "line %d, column %d", &line, &col) != 2) return {0, 0};
    return {line, col};
}

// A syntax error found at a token of several characters (a string, a number,
// a literal) may be reported at its first or its last character.
#define EXPECT_AT_TOKEN(msg, line, first_col, last_col)                                          \
    do {                                                                                         \
        const auto lc_ = ::swarmcl::iotest::line_column(msg);                                    \
        EXPECT_EQ(lc_.first, (line)) << (msg);                                                   \
        EXPECT_TRUE(lc_.second >= (first_col) && lc_.second <= (last_col))                       \
            << "column " << lc_.second << " not in [" << (first_col) << ", " << (last_col) << "]: " << (msg); \
    } while (0)

template <typename T>
std::vector<T> as_vector(const std::string& bytes) {
    std::vector<T> v(bytes.size() / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
    return v;
}

}  // namespace swarmcl::iotest
