// Every write goes through AtomicFile: a failed write leaves neither a
// partial file nor a temporary behind, and an existing file is replaced only
// by a complete one.

#include "recon/io/atomic_file.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/errors.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

TEST(AtomicWriteIo, MissingFolderIsAnIoErrorAndCreatesNothing) {
  TempFolder folder;
  const std::string message =
      testing::message_of<IoError>([&] { write_points(folder / "no" / "such" / "a.ply", random_cloud(5, false, 1)); });
  EXPECT_CONTAINS(message, "a.ply");
  EXPECT_CONTAINS(message, "does not exist");
  EXPECT_TRUE(folder.entries().empty());
  Mesh mesh;
  EXPECT_THROW(write_mesh(folder / "missing" / "m.obj", mesh), IoError);
  EXPECT_TRUE(folder.entries().empty());
}

TEST(AtomicWriteIo, ExceptionMidWriteLeavesNoFile) {
  TempFolder folder;
  try {
    AtomicFile file(folder / "a.xyz");
    file.stream() << "1 2 3\n";
    EXPECT_EQ(folder.entries().size(), 1U);  // only the temporary, under another name
    EXPECT_NE(folder.entries()[0], "a.xyz");
    throw std::runtime_error("simulated failure");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(folder.entries().empty());
}

TEST(AtomicWriteIo, SignalCleanUpRemovesOnlyPendingTemporaries) {
  // What the program's SIGINT handler calls: every temporary still being
  // written goes; committed files and the previous outputs stay.
  TempFolder folder;
  write_file(folder / "kept.xyz", "previous\n");
  {
    AtomicFile done(folder / "done.xyz");
    done.stream() << "1 2 3\n";
    done.commit();
  }
  AtomicFile first(folder / "kept.xyz");
  AtomicFile second(folder / "other.xyz");
  first.stream() << "4 5 6\n";
  EXPECT_EQ(folder.entries().size(), 4U);  // kept, done, and two temporaries
  remove_pending_temporaries();
  EXPECT_EQ(folder.entries(), (std::vector<std::string>{"done.xyz", "kept.xyz"}));
  EXPECT_EQ(read_bytes(folder / "kept.xyz"), "previous\n");
  EXPECT_THROW(second.commit(), IoError);  // its temporary is gone: nothing to rename
  EXPECT_EQ(folder.entries(), (std::vector<std::string>{"done.xyz", "kept.xyz"}));
}

TEST(AtomicWriteIo, ExistingFileIsReplacedOnlyWhenComplete) {
  TempFolder folder;
  write_file(folder / "a.xyz", "old content\n");
  try {
    AtomicFile file(folder / "a.xyz");
    file.stream() << "1 2 3\n";
    file.stream().flush();
    EXPECT_EQ(read_bytes(folder / "a.xyz"), "old content\n");
    throw std::runtime_error("simulated failure");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(read_bytes(folder / "a.xyz"), "old content\n");
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"a.xyz"});

  const PointCloud cloud = random_cloud(10, true, 3);
  write_points(folder / "a.xyz", cloud);
  EXPECT_EQ(read_points(folder / "a.xyz").size(), 10U);
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"a.xyz"});
}

TEST(AtomicWriteIo, RefusedCloudLeavesTheOldFileIntact) {
  TempFolder folder;
  write_points(folder / "a.ply", random_cloud(10, false, 3));
  const std::string before = read_bytes(folder / "a.ply");
  PointCloud bad = random_cloud(10, false, 4);
  bad.positions[5].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_points(folder / "a.ply", bad), InvalidInputError);
  EXPECT_EQ(read_bytes(folder / "a.ply"), before);
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"a.ply"});
}

TEST(AtomicWriteIo, EveryWriterLeavesOnlyItsFile) {
  TempFolder folder;
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  write_mesh(folder / "m.ply", mesh);
  write_mesh(folder / "m.obj", mesh);
  write_mesh(folder / "m.off", mesh);
  write_mesh(folder / "m.stl", mesh);
  write_points(folder / "p.ply", random_cloud(4, false, 1), {.ascii = true});
  write_points(folder / "p.xyz", random_cloud(4, false, 1));
  EXPECT_EQ(folder.entries(), (std::vector<std::string>{"m.obj", "m.off", "m.ply", "m.stl", "p.ply", "p.xyz"}));
}

}  // namespace
}  // namespace recon::io
