// Files written by the library: AtomicFile (complete or absent, also on a
// full disk) and the Recorder's CSV, .npy, .vtp and .pvd outputs, read back
// by the formats' own rules.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/recorder.hpp"
#include "io_test_support.hpp"

namespace {

using namespace swarmcl;
using namespace swarmcl::iotest;

// Resets the full-disk seam even when a test fails half-way.
struct SeamGuard {
    explicit SeamGuard(long long bytes) { AtomicFile::fail_after_bytes_for_testing(bytes); }
    ~SeamGuard() { AtomicFile::fail_after_bytes_for_testing(-1); }
};

// Runs f, which must throw swarmcl::Error; returns it.
template <typename F>
Error expect_error(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "threw a non-swarmcl exception: " << e.what();
        return Error(Status::Internal, e.what());
    }
    ADD_FAILURE() << "did not throw";
    return Error(Status::Ok, "");
}

std::string binary_blob(size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::string s(n, '\0');
    for (auto& c : s) c = char(rng() & 0xFF);
    return s;
}

// ---- AtomicFile ------------------------------------------------------------

TEST(AtomicFile, CommitMakesTheFileAppearWithExactBytes) {
    TempDir dir;
    const std::string target = dir / "data.bin";
    const std::string blob = binary_blob(100000, 1);  // includes '\0', '\n', 0xFF ...
    {
        AtomicFile f(target);
        EXPECT_EQ(f.path(), target);
        f.write(blob.data(), 50000);
        f.write(std::string("middle"));
        f.write(blob.data() + 50000, blob.size() - 50000);
        f.write_at(0, "HEAD", 4);  // a header known only at the end
        // Before commit: the target does not exist, only one temporary beside it.
        EXPECT_FALSE(fs::exists(target));
        const auto names = list_dir(dir.path());
        ASSERT_EQ(names.size(), 1u);
        EXPECT_EQ(names.begin()->rfind("data.bin", 0), 0u) << *names.begin();
        f.commit();
    }
    std::string expected = blob.substr(0, 50000) + "middle" + blob.substr(50000);
    expected.replace(0, 4, "HEAD");
    EXPECT_EQ(read_bytes(target), expected);
    EXPECT_EQ(list_dir(dir.path()), std::set<std::string>{"data.bin"});  // no temporary left
}

TEST(AtomicFile, WriteAtDoesNotMoveTheAppendPosition) {
    TempDir dir;
    AtomicFile f(dir / "x.txt");
    f.write(std::string("0123456789"));
    f.write_at(2, "ab", 2);
    f.write(std::string("XY"));
    f.commit();
    EXPECT_EQ(read_bytes(dir / "x.txt"), "01ab456789XY");
}

TEST(AtomicFile, CommittedFileHasTheUsualPermissions) {
    // A file the user asked for is created as fopen() would: 0666 & ~umask,
    // not the 0600 of a private temporary file.
    TempDir dir;
    const mode_t mask = umask(022);
    umask(mask);
    {
        AtomicFile f(dir / "shared.csv");
        f.write(std::string("a\n"));
        f.commit();
    }
    struct stat st {};
    ASSERT_EQ(stat((dir / "shared.csv").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0666u & ~mask) << std::oct << (st.st_mode & 0777);
}

TEST(AtomicFile, ReplacesAnExistingFileOnlyOnCommit) {
    TempDir dir;
    const std::string target = dir / "keep.txt";
    write_text(target, "old");
    {
        AtomicFile f(target);
        f.write(std::string("new and longer"));
        // abandoned: the old file must be intact
    }
    EXPECT_EQ(read_bytes(target), "old");
    {
        AtomicFile f(target);
        f.write(std::string("new"));
        f.commit();
    }
    EXPECT_EQ(read_bytes(target), "new");
    EXPECT_EQ(list_dir(dir.path()), std::set<std::string>{"keep.txt"});
}

TEST(AtomicFile, AbandonedFileLeavesNothing) {
    TempDir dir;
    {
        AtomicFile f(dir / "half.bin");
        const std::string blob = binary_blob(200000, 2);
        f.write(blob.data(), blob.size());
    }
    EXPECT_TRUE(list_dir(dir.path()).empty());
}

TEST(AtomicFile, CommitTwiceIsAnError) {
    TempDir dir;
    AtomicFile f(dir / "once.txt");
    f.write(std::string("x"));
    f.commit();
    EXPECT_EQ(expect_error([&] { f.commit(); }).status(), Status::Io);
    EXPECT_EQ(expect_error([&] { f.write(std::string("more")); }).status(), Status::Io);
    EXPECT_EQ(read_bytes(dir / "once.txt"), "x");
}

TEST(AtomicFile, FullDiskSeamGivesIoErrorAndLeavesNothing) {
    TempDir dir;
    const std::string target = dir / "full.bin";
    {
        SeamGuard seam(1000);
        AtomicFile f(target);
        f.write(std::string(600, 'a'));  // 600 <= 1000: fine
        const Error e = expect_error([&] { f.write(std::string(600, 'b')); });
        EXPECT_EQ(e.status(), Status::Io);
        EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("No space"), std::string::npos) << e.what();
        // Already gone, before the object is destroyed.
        EXPECT_TRUE(list_dir(dir.path()).empty());
        // The object stays safe to use: further calls are errors, not crashes.
        EXPECT_EQ(expect_error([&] { f.write(std::string("c")); }).status(), Status::Io);
        EXPECT_EQ(expect_error([&] { f.commit(); }).status(), Status::Io);
    }
    EXPECT_TRUE(list_dir(dir.path()).empty());
    // The seam is off again: a big write works.
    AtomicFile g(target);
    g.write(std::string(100000, 'z'));
    g.commit();
    EXPECT_EQ(read_bytes(target).size(), 100000u);
}

TEST(AtomicFile, MissingOrUnwritableFolderIsAnIoError) {
    TempDir dir;
    const std::string missing = dir / "no/such/folder/file.txt";
    Error e = expect_error([&] { AtomicFile f(missing); });
    EXPECT_EQ(e.status(), Status::Io);
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();

    write_text(dir / "regular", "I am a file");
    e = expect_error([&] { AtomicFile f(dir / "regular/file.txt"); });
    EXPECT_EQ(e.status(), Status::Io);

    // /proc refuses new files even for root.
    e = expect_error([&] { AtomicFile f("/proc/swarmcl-test-nope.txt"); });
    EXPECT_EQ(e.status(), Status::Io);
    EXPECT_FALSE(fs::exists("/proc/swarmcl-test-nope.txt"));
    EXPECT_EQ(list_dir(dir.path()), std::set<std::string>{"regular"});
}

TEST(AtomicFile, RenameOntoAFolderFailsCleanly) {
    TempDir dir;
    fs::create_directory(dir / "taken");
    AtomicFile f(dir / "taken");
    f.write(std::string("data"));
    EXPECT_EQ(expect_error([&] { f.commit(); }).status(), Status::Io);
    EXPECT_EQ(list_dir(dir.path()), std::set<std::string>{"taken"});
    EXPECT_TRUE(fs::is_directory(dir / "taken"));
}

// ---- a real full disk --------------------------------------------------------

// A 64 KiB tmpfs, unmounted on destruction; ok() is false where mounting is
// not permitted.
class TinyDisk {
public:
    TinyDisk() {
        if (geteuid() != 0) return;
        std::string pattern = (fs::temp_directory_path() / "swarmcl-tinydisk-XXXXXX").string();
        if (!mkdtemp(pattern.data())) return;
        path_ = pattern;
        const std::string cmd = "mount -t tmpfs -o size=64k tmpfs '" + path_ + "' 2>/dev/null";
        mounted_ = std::system(cmd.c_str()) == 0;
    }
    ~TinyDisk() {
        if (mounted_) {
            const std::string cmd = "umount '" + path_ + "' 2>/dev/null";
            if (std::system(cmd.c_str()) != 0) std::system(("umount -l '" + path_ + "' 2>/dev/null").c_str());
        }
        if (!path_.empty()) rmdir(path_.c_str());
    }
    bool ok() const { return mounted_; }
    const std::string& path() const { return path_; }

private:
    std::string path_;
    bool mounted_ = false;
};

TEST(FullDisk, AtomicFileOnATinyTmpfs) {
    TinyDisk disk;
    if (!disk.ok()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    const std::string target = disk.path() + "/big.bin";
    const Error e = expect_error([&] {
        AtomicFile f(target);
        const std::string chunk(8192, 'x');
        for (int i = 0; i < 64; ++i) f.write(chunk);  // 512 KiB into 64 KiB
        f.commit();
    });
    EXPECT_EQ(e.status(), Status::Io);
    EXPECT_NE(std::string(e.what()).find("No space"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    EXPECT_TRUE(list_dir(disk.path()).empty());
}

TEST(FullDisk, RecorderFailsWithIoAndLeavesNoCompleteLookingFile) {
    TinyDisk disk;
    if (!disk.ok()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    const uint32_t n = 100;
    std::vector<float> pos(3 * n), vel(3 * n);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-10, 10);
    bool failed = false;
    uint32_t frames_done = 0;
    {
        Recorder rec(disk.path(), "swarm", all_export_formats());
        for (uint32_t frame = 0; frame < 1000 && !failed; ++frame) {
            for (auto& x : pos) x = u(rng);
            for (auto& x : vel) x = u(rng);
            try {
                rec.add_frame(frame, frame * 0.1, pos.data(), vel.data(), n);
                ++frames_done;
            } catch (const Error& e) {
                failed = true;
                EXPECT_EQ(e.status(), Status::Io) << e.what();
                EXPECT_NE(std::string(e.what()).find("No space"), std::string::npos) << e.what();
            }
        }
        if (!failed) {
            try {
                rec.finish();
            } catch (const Error& e) {
                failed = true;
                EXPECT_EQ(e.status(), Status::Io) << e.what();
            }
        }
        ASSERT_TRUE(failed) << "1000 frames of 100 agents fit into 64 KiB?";
        EXPECT_GT(frames_done, 0u);
    }
    // The recorder is gone without a successful finish: nothing is left that
    // could be mistaken for a finished output (no CSV, .npy, .vtp, .pvd, and
    // no temporaries).
    EXPECT_TRUE(list_dir(disk.path()).empty()) << "left: " << [&] {
        std::string s;
        for (const auto& f : list_dir(disk.path())) s += f + " ";
        return s;
    }();
}

// ---- Recorder ------------------------------------------------------------------

struct Frames {
    uint32_t n;
    std::vector<uint32_t> numbers;
    std::vector<double> times;
    std::vector<std::vector<float>> pos, vel;
};

Frames make_frames(uint32_t n, uint32_t count, uint32_t seed) {
    Frames f;
    f.n = n;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-100, 100);
    std::uniform_int_distribution<int> e(-30, 30);
    for (uint32_t k = 0; k < count; ++k) {
        f.numbers.push_back(k * 5);  // not the frame index: file names use the number
        f.times.push_back(k * 5 * 0.0333333);
        std::vector<float> p(3 * n), v(3 * n);
        for (auto& x : p) x = std::ldexp(u(rng), e(rng));  // all magnitudes, both signs
        for (auto& x : v) x = u(rng);
        if (n > 2) {
            p[0] = 0.0f;
            p[1] = -0.0f;
            p[2] = 1e-38f;  // subnormal-ish and tiny values survive the text round trip
            v[0] = std::numeric_limits<float>::max();
            v[1] = std::numeric_limits<float>::denorm_min();
            v[2] = 0.1f;
        }
        f.pos.push_back(p);
        f.vel.push_back(v);
    }
    return f;
}

void record(Recorder& rec, const Frames& f) {
    for (size_t k = 0; k < f.pos.size(); ++k) rec.add_frame(f.numbers[k], f.times[k], f.pos[k].data(), f.vel[k].data(), f.n);
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Recorder, CsvRoundTripsEveryFloatExactly) {
    TempDir dir;
    const Frames f = make_frames(7, 4, 11);
    {
        Recorder rec(dir.path(), "traj", kExportCsv);
        record(rec, f);
        EXPECT_EQ(rec.frames(), 4u);
        rec.finish();
        EXPECT_EQ(rec.files(), std::vector<std::string>{dir / "traj.csv"});
    }
    EXPECT_EQ(list_dir(dir.path()), std::set<std::string>{"traj.csv"});
    const auto rows = parse_trajectory_csv(read_bytes(dir / "traj.csv"));
    ASSERT_EQ(rows.size(), 4u * 7u);
    for (uint32_t k = 0; k < 4; ++k)
        for (uint32_t i = 0; i < 7; ++i) {
            const CsvRow& r = rows[k * 7 + i];
            EXPECT_EQ(r.id, i);
            EXPECT_EQ(r.frame, f.numbers[k]);
            for (int a = 0; a < 3; ++a) {
                EXPECT_TRUE(same_bits(r.p[a], f.pos[k][3 * i + a])) << r.p[a] << " vs " << f.pos[k][3 * i + a];
                EXPECT_TRUE(same_bits(r.v[a], f.vel[k][3 * i + a])) << r.v[a] << " vs " << f.vel[k][3 * i + a];
            }
        }
}

TEST(Recorder, NpyHeaderFollowsTheFormatAndDataRoundTrips) {
    TempDir dir;
    const Frames f = make_frames(9, 3, 12);
    {
        Recorder rec(dir.path(), "traj", kExportNpy);
        record(rec, f);
        rec.finish();
    }
    EXPECT_EQ(list_dir(dir.path()), (std::set<std::string>{"traj_positions.npy", "traj_velocities.npy"}));
    for (const bool positions : {true, false}) {
        const Npy npy = read_npy(dir / (positions ? "traj_positions.npy" : "traj_velocities.npy"));
        EXPECT_EQ(npy.descr, "<f4");
        EXPECT_FALSE(npy.fortran_order);
        EXPECT_EQ(npy.shape, (std::vector<uint64_t>{3, 9, 3}));
        ASSERT_EQ(npy.data.size(), 3u * 9u * 3u * sizeof(float));  // nothing before, nothing after
        const auto values = as_vector<float>(npy.data);
        for (size_t k = 0; k < 3; ++k)
            for (size_t j = 0; j < 27; ++j)
                EXPECT_TRUE(same_bits(values[k * 27 + j], (positions ? f.pos : f.vel)[k][j])) << k << "," << j;
    }
}

TEST(Recorder, NpyOfZeroFramesIsAnEmptyArray) {
    TempDir dir;
    {
        Recorder rec(dir.path(), "empty", kExportNpy);
        rec.finish();
    }
    const Npy npy = read_npy(dir / "empty_positions.npy");
    ASSERT_EQ(npy.shape.size(), 3u);
    EXPECT_EQ(npy.shape[0], 0u);
    EXPECT_EQ(npy.shape[2], 3u);
    EXPECT_TRUE(npy.data.empty());
}

TEST(Recorder, NumpyLoadsTheNpyFiles) {
    // The real reader, where Python with NumPy is installed.
    if (std::system("python3 -c 'import numpy' >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3 with numpy";
    TempDir dir;
    const Frames f = make_frames(5, 2, 13);
    {
        Recorder rec(dir.path(), "traj", kExportNpy);
        record(rec, f);
        rec.finish();
    }
    char expected[64];
    std::snprintf(expected, sizeof expected, "%.9g", double(f.pos[1][3 * 4 + 2]));
    const std::string script = "import numpy as np; a = np.load('" + (dir / "traj_positions.npy") +
                               "'); b = np.load('" + (dir / "traj_velocities.npy") +
                               "'); assert a.shape == (2, 5, 3) and b.shape == (2, 5, 3), (a.shape, b.shape); "
                               "assert a.dtype == np.float32; assert a[1, 4, 2] == np.float32('" +
                               expected + "'), a[1, 4, 2]";
    EXPECT_EQ(std::system(("python3 -c \"" + script + "\"").c_str()), 0) << script;
}

TEST(Recorder, VtpBlocksReadBackAndPvdListsEveryFrame) {
    TempDir dir;
    const Frames f = make_frames(6, 3, 14);
    std::vector<std::string> files;
    {
        Recorder rec(dir.path(), "swarm", kExportVtp);
        record(rec, f);
        rec.finish();
        files = rec.files();
    }
    const std::set<std::string> expected_names{"swarm_000000.vtp", "swarm_000005.vtp", "swarm_000010.vtp", "swarm.pvd"};
    EXPECT_EQ(list_dir(dir.path()), expected_names);
    EXPECT_EQ(std::set<std::string>(files.begin(), files.end()),
              (std::set<std::string>{dir / "swarm_000000.vtp", dir / "swarm_000005.vtp", dir / "swarm_000010.vtp",
                                     dir / "swarm.pvd"}));
    const auto pvd = read_pvd(dir / "swarm.pvd");
    ASSERT_EQ(pvd.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "swarm_%06u.vtp", f.numbers[k]);
        EXPECT_EQ(pvd[k].first, name);  // relative to the .pvd, so the folder can move
        EXPECT_NEAR(pvd[k].second, f.times[k], 1e-8 * std::max(1.0, f.times[k]));

        const Vtp vtp = read_vtp(dir / name);
        EXPECT_EQ(vtp.points, 6u);
        EXPECT_EQ(vtp.verts, 6u);
        ASSERT_EQ(vtp.arrays.size(), 5u);
        const auto& points = vtp.arrays.at("Points");
        EXPECT_EQ(points.type, "Float32");
        EXPECT_EQ(points.components, 3);
        const auto& v = vtp.arrays.at("v");
        EXPECT_EQ(v.type, "Float32");
        EXPECT_EQ(v.components, 3);
        EXPECT_EQ(as_vector<float>(points.bytes).size(), 18u);
        EXPECT_EQ(std::memcmp(points.bytes.data(), f.pos[k].data(), std::min<size_t>(points.bytes.size(), 72)), 0);
        EXPECT_EQ(std::memcmp(v.bytes.data(), f.vel[k].data(), std::min<size_t>(v.bytes.size(), 72)), 0);
        EXPECT_EQ(v.bytes.size(), 72u);
        const auto& id = vtp.arrays.at("id");
        EXPECT_TRUE(id.type == "UInt32" || id.type == "Int32") << id.type;
        EXPECT_EQ(as_vector<uint32_t>(id.bytes), (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
        const auto& conn = vtp.arrays.at("connectivity");
        EXPECT_EQ(conn.type, "Int32");
        EXPECT_EQ(as_vector<int32_t>(conn.bytes), (std::vector<int32_t>{0, 1, 2, 3, 4, 5}));
        const auto& offs = vtp.arrays.at("offsets");
        EXPECT_EQ(offs.type, "Int32");
        EXPECT_EQ(as_vector<int32_t>(offs.bytes), (std::vector<int32_t>{1, 2, 3, 4, 5, 6}));
        // The vertex cells sit inside <Verts>.
        const size_t verts = vtp.xml.find("<Verts>");
        ASSERT_NE(verts, std::string::npos);
        EXPECT_GT(vtp.xml.find("Name=\"connectivity\""), verts);
        EXPECT_LT(vtp.xml.find("Name=\"offsets\""), vtp.xml.find("</Verts>"));
    }
}

TEST(Recorder, AllFormatsTogether) {
    TempDir dir;
    const Frames f = make_frames(4, 2, 15);
    {
        Recorder rec(dir.path() + "/nested/out", "all", all_export_formats());  // folders are created
        record(rec, f);
        rec.finish();
        EXPECT_EQ(rec.files().size(), 1u + 2u + 2u + 1u);
    }
    EXPECT_EQ(list_dir(dir / "nested/out"),
              (std::set<std::string>{"all.csv", "all_positions.npy", "all_velocities.npy", "all_000000.vtp",
                                     "all_000005.vtp", "all.pvd"}));
    EXPECT_EQ(parse_trajectory_csv(read_bytes(dir / "nested/out/all.csv")).size(), 8u);
    EXPECT_EQ(read_npy(dir / "nested/out/all_velocities.npy").shape, (std::vector<uint64_t>{2, 4, 3}));
}

TEST(Recorder, WithoutFinishNothingIsLeft) {
    TempDir dir;
    const Frames f = make_frames(5, 3, 16);
    {
        Recorder rec(dir.path(), "lost", all_export_formats());
        record(rec, f);
        // .vtp frames are committed as they come ...
        EXPECT_TRUE(fs::exists(dir / "lost_000000.vtp"));
        EXPECT_TRUE(fs::exists(dir / "lost_000010.vtp"));
    }
    // ... and removed with everything else when the recorder is abandoned.
    EXPECT_TRUE(list_dir(dir.path()).empty());
}

TEST(Recorder, ChangingAgentCountWithNpyIsRejectedAndRecorderStaysUsable) {
    TempDir dir;
    const Frames f = make_frames(4, 2, 17);
    const Frames g = make_frames(5, 1, 18);
    {
        Recorder rec(dir.path(), "n", kExportNpy | kExportCsv);
        rec.add_frame(0, 0.0, f.pos[0].data(), f.vel[0].data(), 4);
        const Error e = expect_error([&] { rec.add_frame(1, 0.1, g.pos[0].data(), g.vel[0].data(), 5); });
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_EQ(rec.frames(), 1u);
        rec.add_frame(2, 0.2, f.pos[1].data(), f.vel[1].data(), 4);
        rec.finish();
    }
    const Npy npy = read_npy(dir / "n_positions.npy");
    EXPECT_EQ(npy.shape, (std::vector<uint64_t>{2, 4, 3}));
    EXPECT_EQ(npy.data.size(), 2u * 4u * 12u);
    const auto rows = parse_trajectory_csv(read_bytes(dir / "n.csv"));
    ASSERT_EQ(rows.size(), 8u);  // the rejected frame wrote nothing
    EXPECT_EQ(rows[4].frame, 2u);
}

TEST(Recorder, ChangingAgentCountIsFineForCsvAndVtp) {
    TempDir dir;
    const Frames f = make_frames(4, 1, 19);
    const Frames g = make_frames(6, 1, 20);
    {
        Recorder rec(dir.path(), "n", kExportCsv | kExportVtp);
        rec.add_frame(0, 0.0, f.pos[0].data(), f.vel[0].data(), 4);
        rec.add_frame(1, 0.1, g.pos[0].data(), g.vel[0].data(), 6);
        rec.finish();
    }
    EXPECT_EQ(parse_trajectory_csv(read_bytes(dir / "n.csv")).size(), 10u);
    EXPECT_EQ(read_vtp(dir / "n_000001.vtp").points, 6u);
}

TEST(Recorder, BadArguments) {
    TempDir dir;
    EXPECT_EQ(expect_error([&] { Recorder r(dir.path(), "x", 8); }).status(), Status::InvalidArgument);
    EXPECT_EQ(expect_error([&] { Recorder r(dir.path(), "x", kExportCsv | 0x100); }).status(), Status::InvalidArgument);
    EXPECT_EQ(expect_error([&] { Recorder r(dir.path(), "", kExportCsv); }).status(), Status::InvalidArgument);
    EXPECT_EQ(expect_error([&] { Recorder r(dir.path(), "a/b", kExportCsv); }).status(), Status::InvalidArgument);
    EXPECT_TRUE(list_dir(dir.path()).empty());

    write_text(dir / "file", "x");
    const Error e = expect_error([&] { Recorder r(dir / "file/sub", "x", kExportCsv); });
    EXPECT_EQ(e.status(), Status::Io);
    EXPECT_NE(std::string(e.what()).find(dir / "file/sub"), std::string::npos) << e.what();
    EXPECT_EQ(expect_error([&] { Recorder r("/proc/swarmcl-nope", "x", kExportCsv); }).status(), Status::Io);
    EXPECT_FALSE(fs::exists("/proc/swarmcl-nope"));

    Recorder rec(dir / "ok", "x", kExportCsv);
    EXPECT_EQ(expect_error([&] { rec.add_frame(0, 0, nullptr, nullptr, 3); }).status(), Status::InvalidArgument);
    rec.finish();
    const float p[3] = {1, 2, 3};
    EXPECT_EQ(expect_error([&] { rec.add_frame(1, 0, p, p, 1); }).status(), Status::InvalidArgument);
    EXPECT_EQ(expect_error([&] { rec.finish(); }).status(), Status::InvalidArgument);
    EXPECT_EQ(parse_trajectory_csv(read_bytes(dir / "ok/x.csv")).size(), 0u);
}

TEST(Recorder, ParseExportFormats) {
    EXPECT_EQ(parse_export_formats("csv"), uint32_t(kExportCsv));
    EXPECT_EQ(parse_export_formats("npy,vtp"), uint32_t(kExportNpy | kExportVtp));
    EXPECT_EQ(parse_export_formats("csv,npy,vtp"), all_export_formats());
    const Error e = expect_error([] { parse_export_formats("csv,gif"); });
    EXPECT_EQ(e.status(), Status::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("gif"), std::string::npos) << e.what();
    EXPECT_EQ(expect_error([] { parse_export_formats("CSV"); }).status(), Status::InvalidArgument);
}

TEST(Recorder, SimulatedFullDiskMidRunLeavesNothing) {
    TempDir dir;
    const Frames f = make_frames(50, 20, 21);
    for (const uint32_t formats : {uint32_t(kExportCsv), uint32_t(kExportNpy), uint32_t(kExportVtp), all_export_formats()}) {
        SeamGuard seam(20000);
        bool failed = false;
        {
            Recorder rec(dir / "run", "s", formats);
            try {
                record(rec, f);
                rec.finish();
            } catch (const Error& e) {
                failed = true;
                EXPECT_EQ(e.status(), Status::Io) << e.what();
                EXPECT_NE(std::string(e.what()).find("No space"), std::string::npos) << e.what();
            }
        }
        EXPECT_TRUE(failed) << "formats " << formats;
        EXPECT_TRUE(list_dir(dir / "run").empty()) << "formats " << formats;
    }
}

}  // namespace
