// Writing an output: through a link to the file it names, in place into a fifo or device, and never a
// cut-off file under the output's name (black-box testing: renaming over a link, a fifo or /dev/null
// replaced them with regular files; a full disk left a cut-off mesh with exit 0).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <string>
#include <thread>

#include "test_support.hpp"
#include "tiltfield/core/io.hpp"
#include "tiltfield/core/mesh.hpp"

namespace {
namespace fs = std::filesystem;

TEST(AtomicWrite, ThroughALinkToTheFileItNames) {
  tf::test::TempDir dir;
  fs::create_symlink("target.txt", dir / "link.txt");  // a file not made yet
  tf::write_file_atomic(dir / "link.txt", [](std::ostream& out) { out << "one"; });
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(tf::test::read_text(dir / "target.txt"), "one");
  tf::write_file_atomic(dir / "link.txt", [](std::ostream& out) { out << "two"; });
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(tf::test::read_text(dir / "target.txt"), "two");
}

TEST(AtomicWrite, IntoAFifoInPlace) {
  tf::test::TempDir dir;
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = tf::test::read_text(fifo); });
  tf::write_file_atomic(fifo, [](std::ostream& out) { out << "through the pipe"; });
  reader.join();
  EXPECT_EQ(got, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST(AtomicWrite, AFailedWriteLeavesTheEarlierFile) {
  tf::test::TempDir dir;
  tf::test::write_text(dir / "out.ply", "KEEP");
  tf::Mesh mesh;
  for (int i = 0; i < 2000; ++i) {  // about 60 KB of binary PLY
    const auto a = mesh.add_vertex({double(i), 0, 0}), b = mesh.add_vertex({double(i), 1, 0}),
               c = mesh.add_vertex({double(i), 0, 1});
    mesh.add_face(a, b, c);
  }
  // A file-size limit of 16 KB: the write fails with EFBIG (the signal ignored), as on a full disk.
  struct rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = old_limit;
  small.rlim_cur = 16384;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string what;
  try {
    tf::write_mesh(mesh, dir / "out.ply");
  } catch (const std::exception& e) {
    what = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(what.find("write failed"), std::string::npos) << what;
  EXPECT_EQ(tf::test::read_text(dir / "out.ply"), "KEEP");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1);  // no temporary left
}

}  // namespace
