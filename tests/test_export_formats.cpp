// The trajectory export formats: the files the Recorder writes, byte for
// byte as before the formats moved behind one writer interface (the hashes
// below were taken from the recorder of commit 45d99d5, whose three formats
// were bitmask branches), and the one table of formats that names them.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <swarmcl/swarmcl.h>

#include "core/error.hpp"
#include "io/export_format.hpp"
#include "io/recorder.hpp"
#include "io_test_support.hpp"

namespace {

using namespace swarmcl;
using namespace swarmcl::iotest;

// FNV-1a, 64 bits: a file's bytes in one number.
uint64_t fnv1a(const std::string& bytes) {
    uint64_t h = 1469598103934665603ull;
    for (const unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}

// Frames of values chosen by arithmetic alone (no library RNG), with
// fractions, negatives and large and small magnitudes for "%.9g".
void record_fixed(Recorder& rec, uint32_t n, uint32_t frames) {
    std::vector<float> pos(3 * size_t(n)), vel(3 * size_t(n));
    for (uint32_t f = 0; f < frames; ++f) {
        for (uint32_t i = 0; i < 3 * n; ++i) {
            pos[i] = float(int(i * 37 + f * 11) % 101 - 50) * 0.173f + float(f) * 1e-3f;
            vel[i] = float(int(i * 53 + f * 7) % 89 - 44) * 3.1e-4f * (i % 5 == 0 ? 1e5f : 1.0f);
        }
        rec.add_frame(f * 5, f * 0.05, pos.data(), vel.data(), n);
    }
}

std::map<std::string, uint64_t> hashes_of(const std::string& dir) {
    std::map<std::string, uint64_t> h;
    for (const std::string& name : list_dir(dir)) h[name] = fnv1a(read_bytes(dir + "/" + name));
    return h;
}

TEST(ExportFormats, EveryFormatWritesTheSameBytesAsBefore) {
    TempDir dir;
    {
        Recorder rec(dir.path(), "gold", kExportCsv | kExportNpy | kExportVtp);
        record_fixed(rec, 7, 3);
        rec.finish();
    }
    {
        Recorder rec(dir.path(), "empty", kExportCsv | kExportNpy | kExportVtp);  // no frame
        rec.finish();
    }
    const std::map<std::string, uint64_t> expected = {
        {"empty.csv", 547895297906977925ull},
        {"empty.pvd", 389546547137365518ull},
        {"empty_positions.npy", 9427863933901106088ull},
        {"empty_velocities.npy", 9427863933901106088ull},
        {"gold.csv", 17916391403129533318ull},
        {"gold.pvd", 2265107742760449133ull},
        {"gold_000000.vtp", 18043190201184074236ull},
        {"gold_000005.vtp", 9130963956559620797ull},
        {"gold_000010.vtp", 10459291540899402720ull},
        {"gold_positions.npy", 3295990210625148856ull},
        {"gold_velocities.npy", 10593224004112839351ull},
    };
    const auto got = hashes_of(dir.path());
    EXPECT_EQ(got, expected);
}

// Every row of the table: one bit of its own, a name of its own that the C
// API gives back, and a writer that writes files alone.
TEST(ExportFormats, EveryRowHasItsOwnBitNameAndWriter) {
    uint32_t seen = 0;
    std::set<std::string> names;
    std::string list;
    for (const ExportFormatInfo& f : export_formats()) {
        SCOPED_TRACE(f.name);
        EXPECT_EQ(f.bit & (f.bit - 1), 0u) << "one bit";
        EXPECT_NE(f.bit, 0u);
        EXPECT_EQ(seen & f.bit, 0u) << "a bit of its own";
        seen |= f.bit;
        EXPECT_TRUE(names.insert(f.name).second) << "a name of its own";
        ASSERT_NE(swcl_export_format_name(f.bit), nullptr);
        EXPECT_STREQ(swcl_export_format_name(f.bit), f.name);
        EXPECT_EQ(find_export_format(f.name), &f);
        EXPECT_EQ(export_format_names(f.bit), std::vector<std::string>{f.name});
        list += (list.empty() ? "" : ",") + std::string(f.name);

        TempDir dir;
        {
            Recorder rec(dir.path(), "one", f.bit);
            record_fixed(rec, 3, 2);
            rec.finish();
            EXPECT_FALSE(rec.files().empty());
            EXPECT_EQ(rec.files().size(), list_dir(dir.path()).size());
        }
    }
    EXPECT_EQ(seen, all_export_formats());
    EXPECT_EQ(parse_export_formats(list), all_export_formats());
    uint32_t parsed = 0;
    ASSERT_EQ(swcl_export_formats_parse(list.c_str(), &parsed), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(parsed, all_export_formats());
    EXPECT_EQ(export_format_names(kExportCsv | kExportVtp), (std::vector<std::string>{"csv", "vtp"}));
    EXPECT_EQ(swcl_export_format_name(0), nullptr);
    EXPECT_EQ(swcl_export_format_name(kExportCsv | kExportNpy), nullptr);
    EXPECT_EQ(swcl_export_format_name(1u << 30), nullptr);
}

TEST(ExportFormats, BadNamesAreRefusedNamingTheKnownOnes) {
    for (const char* bad : {"csv,gif", "CSV", "", "csv,", ",npy", "csv,,vtp", "csv npy"}) {
        SCOPED_TRACE(bad);
        try {
            parse_export_formats(bad);
            ADD_FAILURE() << "accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("csv, npy or vtp"), std::string::npos) << e.what();
        }
        uint32_t out = 12345;
        EXPECT_EQ(swcl_export_formats_parse(bad, &out), SWCL_ERROR_INVALID_ARGUMENT);
        EXPECT_EQ(out, 12345u) << "unchanged";
        EXPECT_NE(std::string(swcl_last_error()).find("csv, npy or vtp"), std::string::npos) << swcl_last_error();
    }
    try {
        parse_export_formats("csv,gif");
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'gif'"), std::string::npos) << e.what();
    }
    uint32_t out = 0;
    EXPECT_EQ(swcl_export_formats_parse(nullptr, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_export_formats_parse("csv", nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_THROW(export_format_names(8), Error);
    EXPECT_EQ(export_format_choices("\""), "\"csv\", \"npy\" or \"vtp\"");
}

}  // namespace
