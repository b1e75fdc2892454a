// Tests of atomic file writes: complete or untouched, never half-written.
#include "core/atomic_file.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>

#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "core/errors.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {
struct Dir {
  fs::path path = fs::temp_directory_path() / ("cellform-atomic-" + std::to_string(::getpid()));
  Dir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
};
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
std::size_t entries(const fs::path& p) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(p), fs::directory_iterator{}));
}
}  // namespace

TEST_CASE("write_file_atomically writes the whole file", "[core][files]") {
  Dir d;
  const fs::path f = d.path / "a.txt";
  cellform::core::write_file_atomically(f, [](std::ostream& os) { os << "hello"; });
  CHECK(slurp(f) == "hello");
  cellform::core::write_file_atomically(f, [](std::ostream& os) { os << "replaced"; });
  CHECK(slurp(f) == "replaced");
  CHECK(entries(d.path) == 1);
}

TEST_CASE("a failing writer leaves the old file and no temporary", "[core][files]") {
  Dir d;
  const fs::path f = d.path / "a.txt";
  cellform::core::write_file_atomically(f, [](std::ostream& os) { os << "old"; });
  CHECK_THROWS_AS(cellform::core::write_file_atomically(f,
                                                        [](std::ostream& os) {
                                                          os << "half";
                                                          throw std::runtime_error("crash mid-write");
                                                        }),
                  std::runtime_error);
  CHECK(slurp(f) == "old");
  CHECK(entries(d.path) == 1);
}

TEST_CASE("the temporary is a new file: a link at its name is neither followed nor removed", "[core][files]") {
  // the temporary's name was path.tmp-PID, opened to truncate: a link put there (in a shared folder)
  // truncated its target, and the write replaced the link
  Dir d;
  const fs::path f = d.path / "a.txt", victim = d.path / "victim.txt";
  { std::ofstream(victim) << "keep me"; }
  const fs::path trap = d.path / ("a.txt.tmp-" + std::to_string(::getpid()) + "-0");
  fs::create_symlink(victim, trap);
  cellform::core::write_file_atomically(f, [](std::ostream& os) { os << "written"; });
  CHECK(slurp(f) == "written");
  CHECK(slurp(victim) == "keep me");
  CHECK(fs::is_symlink(trap));
  CHECK(entries(d.path) == 3);  // the file, the victim, the link: no temporary left
}

TEST_CASE("a temporary replaced while it is written is neither written to nor put in the file's place",
          "[core][files]") {
  // the temporary was closed once made and opened again by name to write and to sync, and renamed by name
  // (review, December 2026): in a folder others may write to, a link put at its name had its target
  // written, or was renamed over the file. Here the name is swapped for a link while the writer runs
  Dir d;
  const fs::path f = d.path / "a.txt", victim = d.path / "victim.txt";
  { std::ofstream(victim) << "keep me"; }
  const fs::path tmp = d.path / ("a.txt.tmp-" + std::to_string(::getpid()) + "-0");
  CHECK_THROWS_WITH(cellform::core::write_file_atomically(f,
                                                          [&](std::ostream& os) {
                                                            REQUIRE(fs::is_regular_file(tmp));
                                                            fs::remove(tmp);
                                                            fs::create_symlink(victim, tmp);
                                                            os << "written";
                                                          }),
                    Contains("was replaced while it was written"));
  CHECK(slurp(victim) == "keep me");
  CHECK_FALSE(fs::exists(fs::symlink_status(f)));  // nothing was put in the file's place
}

TEST_CASE("unwritable places are reported with the path", "[core][files]") {
  Dir d;
  CHECK_THROWS_WITH(cellform::core::write_file_atomically(d.path / "no" / "such" / "dir.txt", [](std::ostream&) {}),
                    Contains("is not a directory"));
  CHECK_THROWS_WITH(cellform::core::write_file_atomically(d.path, [](std::ostream&) {}),
                    Contains("it is a folder (move that folder away)"));
  std::ofstream(d.path / "file") << "x";
  CHECK_THROWS_AS(cellform::core::ensure_directory(d.path / "file"), cellform::core::FileError);
  CHECK_THROWS_WITH(cellform::core::read_file(d.path / "missing"), Contains("does not exist"));
  fs::create_symlink(d.path / "loop", d.path / "loop");  // a loop of links is there, but cannot be read
  CHECK_THROWS_WITH(cellform::core::read_file(d.path / "loop"), Contains("loop") && !Contains("does not exist"));
  // a pipe would block the reader forever and /dev/zero never ends: refused before opening
  REQUIRE(::mkfifo((d.path / "pipe").c_str(), 0600) == 0);
  CHECK_THROWS_WITH(cellform::core::read_file(d.path / "pipe"), Contains("pipe") && Contains("not a regular file"));
  CHECK_THROWS_WITH(cellform::core::read_file("/dev/zero"), Contains("/dev/zero") && Contains("not a regular file"));
  if (::geteuid() != 0) {  // root may write anywhere
    fs::permissions(d.path, fs::perms::owner_read | fs::perms::owner_exec);
    CHECK_THROWS_AS(cellform::core::write_file_atomically(d.path / "b.txt", [](std::ostream& os) { os << "x"; }),
                    cellform::core::FileError);
    fs::permissions(d.path, fs::perms::owner_all);
  }
}

TEST_CASE("a write that runs out of space is reported, not silently truncated", "[core][files]") {
  // RLIMIT_FSIZE makes writes past 4 KiB fail like a full disk (EFBIG); SIGXFSZ must be ignored for that
  Dir d;
  const fs::path f = d.path / "big.bin";
  cellform::core::write_file_atomically(f, [](std::ostream& os) { os << "old"; });
  rlimit old{};
  getrlimit(RLIMIT_FSIZE, &old);
  auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old;
  small.rlim_cur = 4096;
  setrlimit(RLIMIT_FSIZE, &small);
  bool threw = false;
  std::string message;
  try {
    cellform::core::write_file_atomically(f, [](std::ostream& os) { os << std::string(1 << 20, 'x'); });
  } catch (const cellform::core::FileError& e) {
    threw = true;
    message = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  CHECK(threw);
  CHECK_THAT(message, Catch::Contains("big.bin") && Catch::Contains("ulimit -f"));  // says which limit
  CHECK(slurp(f) == "old");
  CHECK(entries(d.path) == 1);
}
