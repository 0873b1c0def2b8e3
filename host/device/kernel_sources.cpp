#include "device/kernel_sources.hpp"

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.hpp"

namespace swarmcl {
namespace embedded {
struct KernelFile { const char* name; const char* text; };
extern const KernelFile kFiles[];
}  // namespace embedded

namespace {

std::string raw_source(const std::string& name) {
    if (const char* dir = std::getenv("SWARMCL_KERNEL_DIR"); dir && *dir) {
        const std::string path = std::string(dir) + "/" + name;
        std::ifstream in(path, std::ios::binary);
        if (!in) fail(Status::Io, "kernel file '" + path + "' not found (SWARMCL_KERNEL_DIR is set)");
        std::ostringstream text;
        text << in.rdbuf();
        return text.str();
    }
    for (const embedded::KernelFile* f = embedded::kFiles; f->name; ++f)
        if (name == f->name) return f->text;
    fail(Status::Internal, "kernel file '" + name + "' is not embedded in this build");
}

// A per-width body ("wide/x.inc.cl") is expanded at every #include: the
// including file sets the width macro before each one (docs/architecture.md).
// Every other file is expanded once, like #pragma once.
bool included_every_time(const std::string& name) {
    const std::string suffix = ".inc.cl";
    return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void expand(const std::string& name, std::set<std::string>& seen, std::string& out) {
    if (!seen.insert(name).second && !included_every_time(name)) return;
    std::istringstream lines(raw_source(name));
    std::string line;
    int number = 0;
    while (std::getline(lines, line)) {
        ++number;
        const auto first = line.find_first_not_of(" \t");
        if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
            const auto open = line.find('"'), close = line.rfind('"');
            if (open != std::string::npos && close > open) {
                expand(line.substr(open + 1, close - open - 1), seen, out);
                out += "#line " + std::to_string(number + 1) + "\n";
                continue;
            }
        }
        out += line;
        out += '\n';
    }
}

}  // namespace

std::string load_kernel_source(const std::string& name) {
    std::set<std::string> seen;
    std::string out;
    expand(name, seen, out);
    return out;
}

}  // namespace swarmcl
