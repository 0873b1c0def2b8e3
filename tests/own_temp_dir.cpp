// Each test process writes under a temporary folder of its own
// (testing::TempDir() reads TEST_TMPDIR): ctest runs one test binary's
// profiles side by side (its gpu_profile., scalar. and lanes8. twins), and
// tests write fixed file names there, so two copies of a test raced over one
// file (EnergyCapi.DatasetsFromArraysCsvAndFiles failed once that way).
// Linked into every test executable (tests/CMakeLists.txt).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace {

struct OwnTempDir {
    std::string dir;
    OwnTempDir() {
        const char* base = std::getenv("TEST_TMPDIR");
        if (!base || !*base) base = std::getenv("TMPDIR");
        dir = std::string(base && *base ? base : "/tmp") + "/swarmcl-test-" + std::to_string(::getpid());
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (!ec) ::setenv("TEST_TMPDIR", dir.c_str(), 1);
    }
    ~OwnTempDir() {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
    }
};

const OwnTempDir own_temp_dir;

}  // namespace
