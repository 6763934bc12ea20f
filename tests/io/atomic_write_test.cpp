// Every write goes through AtomicFile: a failed write leaves neither a
// partial file nor a temporary behind, and an existing file is replaced only
// by a complete one.

#include "recon/io/atomic_file.h"
#include "recon/io/mesh_io.h"
#include "recon/io/mesh_stream.h"
#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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

// --------------------------------------------------------------------------
// Special targets: links, FIFOs, devices (an output never replaces them)

mode_t mode_of(const std::filesystem::path& path) {
  struct stat status {};
  EXPECT_EQ(::lstat(path.c_str(), &status), 0) << path;
  return status.st_mode;
}

/// A FIFO opened for reading without waiting for a writer, so that a writer
/// can open it in the same thread; reads what is in it (a test writes less
/// than the pipe's buffer).
class FifoReader {
 public:
  explicit FifoReader(const std::filesystem::path& path) {
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK);
    EXPECT_GE(fd_, 0);
  }
  FifoReader(const FifoReader&) = delete;
  FifoReader& operator=(const FifoReader&) = delete;
  ~FifoReader() { ::close(fd_); }
  std::string drain() const {
    std::string text;
    char block[4096];
    for (ssize_t got; (got = ::read(fd_, block, sizeof block)) > 0;) text.append(block, static_cast<std::size_t>(got));
    return text;
  }

 private:
  int fd_ = -1;
};

TEST(AtomicWriteIo, ASymlinkIsWrittenThroughAndStaysALink) {
  // As a shell's '>': the file the link names gets the new content, still
  // atomically (beside it), and the link is not replaced by a file.
  TempFolder folder;
  std::filesystem::create_directory(folder / "real");
  write_file(folder / "real" / "a.xyz", "old\n");
  std::filesystem::create_symlink("real/a.xyz", folder / "link.xyz");
  std::filesystem::create_symlink("link.xyz", folder / "chain.xyz");  // a link to a link
  write_points(folder / "chain.xyz", random_cloud(5, false, 1));
  EXPECT_TRUE(std::filesystem::is_symlink(folder / "link.xyz"));
  EXPECT_TRUE(std::filesystem::is_symlink(folder / "chain.xyz"));
  EXPECT_EQ(read_points(folder / "real" / "a.xyz").size(), 5U);
  EXPECT_EQ(folder.entries(), (std::vector<std::string>{"chain.xyz", "link.xyz", "real"}));
  // A dangling link: its target is created.
  std::filesystem::create_symlink("real/new.ply", folder / "new.ply");
  write_points(folder / "new.ply", random_cloud(4, false, 2));
  EXPECT_TRUE(std::filesystem::is_symlink(folder / "new.ply"));
  EXPECT_EQ(read_points(folder / "real" / "new.ply").size(), 4U);
  const OutputTarget target = output_target(folder / "chain.xyz");
  EXPECT_EQ(target.kind, OutputTarget::Kind::file);
  EXPECT_EQ(std::filesystem::canonical(target.path), std::filesystem::canonical(folder / "real" / "a.xyz"));
}

TEST(AtomicWriteIo, AFifoIsWrittenAsAStreamNotReplaced) {
  TempFolder folder;
  const FifoReader reader(folder / "out.xyz");
  write_points(folder / "out.xyz", random_cloud(3, false, 1));
  const std::string sent = reader.drain();
  EXPECT_EQ(std::count(sent.begin(), sent.end(), '\n'), 3) << sent;
  EXPECT_TRUE(S_ISFIFO(mode_of(folder / "out.xyz")));
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"out.xyz"});
}

TEST(AtomicWriteIo, AStreamedMeshKeepsItsPartsBesideTheFifo) {
  // The tiled writer's two parts are scratch files, never the FIFO itself.
  TempFolder folder;
  const FifoReader reader(folder / "m.ply");
  PlyMeshStream mesh(folder / "m.ply", false);
  mesh.add_vertex({0, 0, 0});
  mesh.add_vertex({1, 0, 0});
  mesh.add_vertex({0, 1, 0});
  mesh.add_triangle({0, 1, 2});
  EXPECT_EQ(folder.entries().size(), 3U);  // the FIFO and the two parts
  mesh.finish();
  EXPECT_TRUE(reader.drain().starts_with("ply\nformat binary_little_endian 1.0\n"));
  EXPECT_TRUE(S_ISFIFO(mode_of(folder / "m.ply")));
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"m.ply"});
}

TEST(AtomicWriteIo, DevicesAreStreamsAndFoldersAreRefused) {
  // Only asked, never written: the decision is made from stat alone.
  EXPECT_EQ(output_target("/dev/null").kind, OutputTarget::Kind::stream);
  EXPECT_EQ(output_target("/dev/null").path, "/dev/null");
  EXPECT_EQ(output_target("/dev/zero").kind, OutputTarget::Kind::stream);
  TempFolder folder;
  const std::string message = testing::message_of<IoError>([&] { static_cast<void>(output_target(folder.path())); });
  EXPECT_CONTAINS(message, ": cannot write: it is a folder");
  EXPECT_EQ(output_target(folder / "new.ply").kind, OutputTarget::Kind::file);
}

TEST(AtomicWriteIo, ADescriptorLinkIsAStreamThatAppends) {
  // /dev/stdout -> /proc/self/fd/1 -> the file a shell opened with '>>':
  // replacing the file, or truncating it, would lose what it held.
  TempFolder folder;
  write_file(folder / "log.txt", "before\n");
  const int fd = ::open((folder / "log.txt").c_str(), O_WRONLY | O_APPEND);
  ASSERT_GE(fd, 0);
  const std::filesystem::path link = folder / "out.xyz";
  std::filesystem::create_symlink("/proc/self/fd/" + std::to_string(fd), link);
  EXPECT_EQ(output_target(link).kind, OutputTarget::Kind::stream);
  {
    AtomicFile file(link);
    file.stream() << "after\n";
    file.commit();
  }
  ::close(fd);
  EXPECT_EQ(read_bytes(folder / "log.txt"), "before\nafter\n");
}

TEST(AtomicWriteIo, ARewrittenFileKeepsItsModeAndOwner) {
  TempFolder folder;
  for (const mode_t mode : {mode_t{0600}, mode_t{0640}, mode_t{0755}}) {
    write_points(folder / "a.ply", random_cloud(4, false, 1));
    ASSERT_EQ(::chmod((folder / "a.ply").c_str(), mode), 0);
    write_points(folder / "a.ply", random_cloud(5, false, 2));
    EXPECT_EQ(mode_of(folder / "a.ply") & 07777, mode);
    EXPECT_EQ(read_points(folder / "a.ply").size(), 5U);
  }
  if (::geteuid() != 0) return;  // only a privileged user can give a file to another owner
  ASSERT_EQ(::chown((folder / "a.ply").c_str(), 12345, 23456), 0);
  write_points(folder / "a.ply", random_cloud(3, false, 3));
  struct stat status {};
  ASSERT_EQ(::stat((folder / "a.ply").c_str(), &status), 0);
  EXPECT_EQ(status.st_uid, 12345U);
  EXPECT_EQ(status.st_gid, 23456U);
}

}  // namespace
}  // namespace recon::io
