// The output folder of a run: its staging folder, the commit of the outputs into it, the frames an
// earlier run left there, and the empty folders a failed run made.
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>

#include "app/run_internal.h"
#include "core/atomic_file.h"
#include "core/errors.h"

namespace cellform::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// What stands at `p` that is not a file: "a folder", "a named pipe", ... (for "'x' is not a file: a folder").
std::string not_a_file(const fs::path& p) {
  std::error_code ec;
  const fs::file_type t = fs::status(p, ec).type();
  return std::string("not a file but ") + (t == fs::file_type::directory ? "a folder"
                                           : t == fs::file_type::fifo    ? "a named pipe"
                                           : t == fs::file_type::socket  ? "a socket"
                                           : t == fs::file_type::block || t == fs::file_type::character
                                               ? "a device"
                                               : "something else");
}

/// Whether process `pid` is running: a zombie (killed, not yet reaped by its parent) is not.
bool process_alive(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return true;  // no /proc: what kill said
  const std::size_t close = line.rfind(')');   // "pid (name) S ...": the name may hold spaces and ')'
  return !(close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'Z');
}

/// The process ids of the live staging folders (".partial-PID") in `dir` other than this process's.
std::vector<long> live_stagings(const fs::path& dir) {
  std::vector<long> out;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".partial-", 0) != 0) continue;
    const std::string digits = name.substr(9, name.find('-', 9) - 9);  // ".partial-PID" or ".partial-PID-K"
    const std::string rest =
        name.find('-', 9) == std::string::npos ? std::string() : name.substr(name.find('-', 9) + 1);
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos ||
        rest.find_first_not_of("0123456789") != std::string::npos || e.is_symlink(ec))
      continue;
    const auto pid = static_cast<pid_t>(std::stol(digits));
    if (pid != ::getpid() && process_alive(pid)) out.push_back(pid);
  }
  return out;
}

/// Whether run.json `j` is cellform's.
bool is_cellform_run(const json& j) { return j.is_object() && j.value("program", std::string()) == "cellform"; }

/// Whether `name`, listed as an output in a run.json, names a file cellform writes inside `dir`: a plain
/// name, or one inside frames/, reached through no symbolic link (a listed "link/x" must not delete a
/// file outside the folder).
bool own_output(const fs::path& dir, const std::string& name) {
  const fs::path p(name);
  if (name.empty() || p.is_absolute() || name.find("..") != std::string::npos) return false;
  std::vector<fs::path> parts(p.begin(), p.end());
  if (parts.size() > 2 || (parts.size() == 2 && parts[0] != "frames")) return false;
  std::error_code ec;
  return parts.size() == 1 || !fs::is_symlink(dir / parts[0], ec);
}

}  // namespace

FolderLock::FolderLock(const fs::path& dir) {
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw core::FileError("cannot open '" + dir.string() + "': " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) return;
  const int why = errno;
  ::close(fd_);
  fd_ = -1;
  if (why != EWOULDBLOCK) return;  // a file system without locks: run unlocked, as before
  std::string who;
  for (const long pid : live_stagings(dir)) who += (who.empty() ? " (process " : ", ") + std::to_string(pid);
  if (!who.empty()) who += ")";
  throw FolderBusy("another cellform run" + who + " is writing to '" + dir.string() +
                   "': wait for it to end, or choose another --out folder");
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

std::optional<std::string> own_record(const fs::path& resumed, const fs::path& dir) {
  std::error_code ec;
  if (!fs::equivalent(resumed, dir / kCheckpointName, ec)) return std::nullopt;
  try {
    return core::read_file(dir / "run.json");
  } catch (const std::exception&) {
    return std::string();
  }
}

std::string output_error(const std::exception& e, const fs::path& staging, const fs::path& dir) {
  std::string m = core::error_text(e);
  if (staging.empty()) return m;
  const std::string from = staging.string() + "/", to = (dir / "").string();
  for (std::size_t at = m.find(from); at != std::string::npos; at = m.find(from, at + to.size()))
    m.replace(at, from.size(), to);
  return m;
}

void drop_earlier_checkpoint(const fs::path& dir, const json& run, const fs::path& resumed) {
  if (!run.contains("checkpoint") || !run["checkpoint"].is_null()) return;
  std::error_code ec;
  if (!resumed.empty() && fs::equivalent(resumed, dir / kCheckpointName, ec)) return;
  fs::remove(dir / kCheckpointName, ec);
}

void mark_superseded(const fs::path& dir) {
  const fs::path file = dir / "run.json";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return;
  json j;
  try {
    std::ifstream in(file);
    j = json::parse(in);
  } catch (const std::exception&) {
    return;  // not cellform's (make_staging refused such a folder); left as it is
  }
  if (!is_cellform_run(j) || j.value("status", std::string()) == "superseded") return;
  j["status"] = "superseded";
  j["superseded"] =
      "checkpoint.cfck in this folder is a later run's, which stopped before it wrote its outputs (a kill, or "
      "Ctrl-C pressed again): cellform resume this folder continues that run; the outputs listed here are this "
      "earlier run's";
  write_run_json(file, j);
}

bool periodic_checkpoint(const std::function<void()>& write, std::ostream& err, bool& warned, double& seconds) {
  const auto began = std::chrono::steady_clock::now();
  struct Clock {
    std::chrono::steady_clock::time_point began;
    double& seconds;
    ~Clock() { seconds += seconds_since(began); }
  } clock{began, seconds};
  try {
    write();
    return true;
  } catch (const core::FileError& e) {
    if (!warned)
      err << "\ncellform: warning: " << e.what()
          << "\n  (the run goes on, and tries again at the next periodic checkpoint and at the end)\n";
    warned = true;
    return false;
  }
}

void record_checkpoint(json& run, const std::string& error, bool earlier_saved,
                       std::optional<std::uint64_t> earlier_step) {
  if (error.empty()) {
    run["checkpoint"] = kCheckpointName;
    return;
  }
  run["checkpoint"] = earlier_saved ? json(kCheckpointName) : json(nullptr);
  if (earlier_saved && earlier_step) run["checkpoint_step"] = *earlier_step;
  run["checkpoint_error"] = error;
}

void write_checkpoint(const fs::path& path, const std::string& bytes) {
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::string before;  // the earlier run's run.json, put back if the checkpoint is not written after all
  std::error_code ec;
  if (fs::is_regular_file(dir / "run.json", ec)) {
    std::ifstream in(dir / "run.json", std::ios::binary);
    if (in) before.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) before.clear();  // not read whole: not put back
  }
  mark_superseded(dir);
  try {
    core::write_file_atomically(
        path, [&](std::ostream& os) { os.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
  } catch (...) {
    // the folder's checkpoint is still the earlier run's (a full disk): its run.json says so again
    if (!before.empty()) try {
        core::write_file_atomically(dir / "run.json", [&](std::ostream& os) {
          os.write(before.data(), static_cast<std::streamsize>(before.size()));
        });
      } catch (const std::exception&) {  // as full as before: the mark stays, the first error is the one said
      }
    throw;
  }
}

fs::path make_staging(const fs::path& dir, std::optional<FolderLock>& lock, fs::path* kept,
                      std::string* checkpoint_mark_out) {
  {
    // --out names a place no folder can be made (a file on the way, /proc, too long a name): an input
    // error; a full or failing disk is not
    std::error_code ec;
    core::ensure_directory(dir, ec);
    if (ec) {
      std::error_code probe;
      const bool dangling = fs::is_symlink(dir, probe) && !fs::exists(dir, probe);
      const std::string what = dangling ? "'" + dir.string() + "' is a symbolic link to '" +
                                              fs::read_symlink(dir, probe).string() + "', which does not exist"
                               : ec == std::errc::not_a_directory && fs::exists(dir, probe)
                                   ? "'" + dir.string() + "' exists and is not a directory"
                                   : "cannot create directory '" + dir.string() + "': " + ec.message();
      if (ec == std::errc::no_space_on_device || ec == std::errc::io_error || ec.value() == EDQUOT)
        throw core::FileError(what);
      throw FolderRefused(what);
    }
  }
  lock.emplace(dir);
  {
    std::error_code ec;
    if (fs::exists(dir / "run.json", ec)) {
      const fs::path file = dir / "run.json";
      if (!fs::is_regular_file(file, ec))
        throw FolderRefused("'" + file.string() + "' is " + not_a_file(file) +
                            "; a run there writes its run.json in its place: choose another --out folder, or move "
                            "that away");
      std::ifstream in(file);
      if (!in)
        throw core::FileError("cannot read '" + file.string() + "' (" + std::strerror(errno) +
                              "); a run there replaces it");
      json j;
      try {
        j = json::parse(in);
      } catch (const std::exception&) {
        throw FolderRefused("'" + file.string() +
                            "' is not valid JSON: cellform writes it whole, so another program "
                            "wrote it, or a disk failed; a run there would replace it: choose another --out "
                            "folder, or move that file away");
      }
      if (!is_cellform_run(j))
        throw FolderRefused("'" + file.string() +
                            "' was not written by cellform; a run there would replace it and delete the files it "
                            "lists: choose another --out folder, or move that file away");
    }
  }
  // staging folders (".partial-PID" or ".partial-PID-K") and half-written checkpoints and run.json files
  // ("checkpoint.cfck.tmp-PID-K", "run.json.tmp-PID-K", ".cellform-outputs.tmp-PID-K") of runs that were killed (a
  // second Ctrl-C, SIGKILL): with the folder locked no other run writes there, so all of them, whatever runs under
  // those process ids now; unlocked (a file system without locks), those whose process is gone
  std::error_code ec;
  const bool locked = lock && lock->held();
  std::string folder_mark;  // of the checkpoint in the folder: the staging folder holding its frames stays
  if (fs::is_regular_file(dir / kCheckpointName, ec)) try {
      folder_mark = checkpoint_mark(core::read_file(dir / kCheckpointName));
    } catch (const std::exception&) {
    }
  auto pid_of = [](const std::string& t) -> long {  // "PID" or "PID-K", else -1
    const std::size_t dash = t.find('-');
    auto digits = [](const std::string& d) {
      return !d.empty() && d.size() <= 9 && d.find_first_not_of("0123456789") == std::string::npos;
    };
    const std::string head = t.substr(0, dash);
    if (!digits(head) || (dash != std::string::npos && !digits(t.substr(dash + 1)))) return -1;
    return std::stol(head);
  };
  std::vector<fs::path> stale;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    std::size_t prefix = 0;
    if (name.rfind(".partial-", 0) == 0 && !e.is_symlink(ec) && e.is_directory(ec))
      prefix = 9;
    else
      for (const std::string& tmp : {std::string(kCheckpointName) + ".tmp-", std::string("run.json.tmp-"),
                                     std::string(kOutputsManifest) + ".tmp-"})
        if (name.rfind(tmp, 0) == 0 && !e.is_symlink(ec) && e.is_regular_file(ec)) prefix = tmp.size();
    const long pid = prefix ? pid_of(name.substr(prefix)) : -1;
    if (pid < 0) continue;
    if (!locked && (pid == ::getpid() || process_alive(static_cast<pid_t>(pid)))) continue;
    if (prefix == 9 && !folder_mark.empty() && kept && kept->empty()) {
      std::ifstream in(e.path() / kStagingMark);
      bool holds = false;
      for (std::string mark; std::getline(in, mark);) holds = holds || mark == folder_mark;
      if (holds) {
        *kept = e.path();
        continue;
      }
    }
    stale.push_back(e.path());
  }
  std::sort(stale.begin(), stale.end());
  for (const fs::path& p : stale) fs::remove_all(p, ec);
  if (checkpoint_mark_out) *checkpoint_mark_out = folder_mark;
  fs::path staging = dir / (".partial-" + std::to_string(::getpid()));
  for (int k = 1; fs::exists(staging, ec) || fs::is_symlink(staging, ec); ++k)  // the kept one, of an earlier
    staging = dir / (".partial-" + std::to_string(::getpid()) + "-" + std::to_string(k));  // run with our pid
  // the longest path a run writes (a frame written aside in the staging folder) must fit the system's
  // limit, else the run would fail only at its end
  const std::string longest = (staging / "frames" / "cells_000000000000000000.ply.tmp-4294967295-99").string();
  if (longest.size() >= PATH_MAX)
    throw FolderRefused("the --out folder's path is too long: its files' paths would pass the system's limit of " +
                        std::to_string(PATH_MAX) + " bytes ('" + dir.string().substr(0, 60) + "...')");
  core::ensure_directory(staging, ec);
  if (ec) {  // a folder no file can be written in (/proc, read-only): an input error; a failing disk is not
    const std::string what = "cannot write in '" + dir.string() + "': " + ec.message();
    if (ec == std::errc::no_space_on_device || ec == std::errc::io_error || ec.value() == EDQUOT)
      throw core::FileError(what);
    throw FolderRefused(what);
  }
  return staging;
}

bool mark_staging(const fs::path& staging, const std::vector<std::string>& marks) {
  try {
    core::write_file_atomically(staging / kStagingMark, [&](std::ostream& os) {
      for (const std::string& m : marks)
        if (!m.empty()) os << m << "\n";
    });
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

std::vector<std::pair<std::uint64_t, std::string>> salvage_frames(const fs::path& from, const fs::path& staging,
                                                                  std::uint64_t up_to) {
  std::vector<std::pair<std::uint64_t, std::string>> found;
  std::error_code ec;
  if (from.empty() || fs::is_symlink(from / "frames", ec) || !fs::is_directory(from / "frames", ec)) return found;
  for (const fs::directory_entry& e : fs::directory_iterator(from / "frames", ec)) {
    const std::string name = e.path().filename().string();  // cells_NNNNNN.ply
    if (name.rfind("cells_", 0) != 0 || name.size() <= 10 || name.substr(name.size() - 4) != ".ply") continue;
    const std::string digits = name.substr(6, name.size() - 10);
    if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 18) continue;
    const std::uint64_t step = std::stoull(digits);
    if (step <= up_to && !e.is_symlink(ec) && e.is_regular_file(ec)) found.emplace_back(step, "frames/" + name);
  }
  std::sort(found.begin(), found.end());
  std::vector<std::pair<std::uint64_t, std::string>> taken;
  for (const auto& [step, name] : found) {
    core::ensure_directory(staging / "frames");
    std::error_code link;
    fs::create_hard_link(from / name, staging / name, link);
    if (link) fs::copy_file(from / name, staging / name, fs::copy_options::overwrite_existing, link);
    if (!link) taken.emplace_back(step, name);
  }
  return taken;
}

namespace {
/// `dir` absolute and normal, without a trailing separator ("a/b/" is "a/b").
fs::path plain_path(const fs::path& dir, std::error_code& ec) {
  fs::path p = fs::absolute(dir, ec).lexically_normal();
  if (p.has_parent_path() && p.filename().empty()) p = p.parent_path();
  return p;
}
}  // namespace

fs::path first_missing(const fs::path& dir) {
  std::error_code ec;
  fs::path missing;
  fs::path p = plain_path(dir, ec);
  if (ec) return missing;
  for (; !p.empty(); p = p.parent_path()) {
    std::error_code there;
    if (fs::exists(p, there) || (there && there != std::errc::filename_too_long))
      break;  // a name too long is not there
    missing = p;
    if (p == p.parent_path()) break;
  }
  return missing;
}

fs::path out_folder(const fs::path& dir) {
  fs::path out;
  std::error_code ec;
  for (const fs::path& part : dir) {
    if (part == "." && !out.empty()) continue;  // "new/./.." is "new/.."
    // nothing at all there (a file or a dangling link is something: the system then says what is wrong)
    const bool missing = !out.empty() && out.filename() != ".." && out.filename() != "." &&
                         out.filename() != out.root_directory() &&
                         fs::symlink_status(out, ec).type() == fs::file_type::not_found;
    if (part == ".." && missing)
      out = out.parent_path();
    else
      out /= part;
  }
  return out.empty() ? fs::path(".") : out;
}

void remove_empty_up_to(const fs::path& dir, const fs::path& top) {
  if (top.empty()) return;
  std::error_code ec;
  fs::path p = plain_path(dir, ec);
  const fs::path stop = plain_path(top, ec);
  // from the deepest folder there is: a failed create_directories may have made only the first few
  while (!ec && p != stop && p != p.parent_path()) {
    std::error_code there;
    if (fs::symlink_status(p, there).type() != fs::file_type::not_found && !there) break;
    p = p.parent_path();
  }
  while (!ec && fs::is_directory(p, ec) && fs::is_empty(p, ec) && !ec) {
    fs::remove(p, ec);
    if (p == stop || p == p.parent_path()) break;
    p = p.parent_path();
  }
}

int refuse_outputs(const std::exception_ptr& e, const fs::path& dir, const fs::path& created, std::ostream& err) {
  try {
    std::rethrow_exception(e);
  } catch (const FolderBusy& b) {
    err << "cellform: cannot write outputs: " << b.what() << "\n";
    return failure;  // the folder is the other run's now
  } catch (const FolderRefused& r) {
    err << "cellform: cannot write outputs: " << r.what() << "\n";
    remove_empty_up_to(dir, created);  // the folders a failed --out made on its way
    return usage;                      // the folder is as it was
  } catch (const std::exception& x) {
    err << "cellform: cannot write outputs: " << core::error_text(x) << "\n";
    remove_empty_up_to(dir, created);
    return failure;
  }
}

bool keep_other_run(const fs::path& dir, const fs::path& resumed, const std::string& checkpoint_error,
                    const fs::path& staging, const fs::path& created, std::ostream& err) {
  const fs::path there = dir / kCheckpointName;
  std::error_code ec;
  if (fs::symlink_status(there, ec).type() != fs::file_type::regular) return false;
  if (!resumed.empty() && fs::equivalent(resumed, there, ec)) return false;
  err << "cellform: " << checkpoint_error << "\n  (this run's outputs are not written, and nothing in " << dir.string()
      << "/ changed: without a checkpoint of its own this run would replace the run there, its checkpoint too, "
         "and leave neither to resume; make room and run or resume again, or give --out another folder)\n";
  fs::remove_all(staging, ec);
  remove_empty_up_to(dir, created);
  return true;
}

std::vector<std::string> earlier_frames(const fs::path& dir, std::uint64_t up_to, const std::string& script_hash,
                                        std::uint64_t seed, const Overrides& overrides) {
  // the overrides that shape the cells (output.* and print.* may change on resume)
  auto shaping = [](const Overrides& all) {
    Overrides out;
    for (const auto& [k, v] : all)
      if (k.rfind("output.", 0) != 0 && k.rfind("print.", 0) != 0) out[k] = v;
    return out;
  };
  std::vector<std::string> kept;
  try {
    std::ifstream old(dir / "run.json");
    if (!old) return kept;
    const json j = json::parse(old);
    if (!is_cellform_run(j)) return kept;
    // frames of this run only: the same script, seed and overrides give the same frames (a run.json older
    // than the checkpoint is fine: its frames are the run's up to where it stopped)
    if (j.at("script").at("hash").get<std::string>() != script_hash || j.at("seed").get<std::uint64_t>() != seed ||
        shaping(j.at("overrides").get<Overrides>()) != shaping(overrides))
      return kept;
    for (const auto& n : j.value("outputs", json::array())) {
      const std::string name = n.get<std::string>();
      // "frames/cells_NNNNNN.ply"
      const std::size_t a = name.rfind('_'), b = name.rfind(".ply");
      if (name.rfind("frames/cells_", 0) != 0 || a == std::string::npos || b == std::string::npos || b <= a + 1 ||
          name.find("..") != std::string::npos)
        continue;
      const std::string digits = name.substr(a + 1, b - a - 1);
      if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 18) continue;
      if (std::stoull(digits) <= up_to && own_output(dir, name) && fs::is_regular_file(dir / name))
        kept.push_back(name);
    }
  } catch (...) {
    // an unreadable old run.json: its frames are not known to be this run's
  }
  return kept;
}

void check_output_places(const fs::path& dir, std::vector<std::string> names) {
  names.insert(names.begin(), {kCheckpointName, "run.json"});
  for (const std::string& name : names) {
    std::error_code probe;
    if (fs::is_directory(dir / name, probe))
      throw FolderRefused("'" + (dir / name).string() + "' is a folder where this run may write its " + name +
                          ": choose another --out folder, or move that folder away");
  }
}

void check_frames_folder(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir / "frames", ec)) && !fs::is_directory(dir / "frames", ec))
    throw FolderRefused("'" + (dir / "frames").string() +
                        "' is not a folder; output.every writes the frames into frames/: choose another --out "
                        "folder, or move that away");
}

/// Moves every file of `staging` (recursively) into `dir`, then removes the outputs of an earlier run
/// (listed in its run.json) that this run did not write again and `keep` does not name.
void commit_outputs(const fs::path& staging, const fs::path& dir, const std::vector<std::string>& names,
                    const std::vector<std::string>& keep) {
  std::set<std::string> fresh(names.begin(), names.end());
  fresh.insert(keep.begin(), keep.end());
  std::vector<std::string> stale;
  bool old_run = false;
  try {
    std::ifstream old(dir / "run.json");
    if (old) {
      const json j = json::parse(old);
      if (is_cellform_run(j)) {
        old_run = true;
        for (const auto& n : j.value("outputs", json::array())) stale.push_back(n.get<std::string>());
      }
    }
  } catch (...) {
    // an unreadable old run.json only means we cannot clean up after it
  }
  // A commit stopped by a kill left the two runs' outputs listed beside them: the file itself only (a link
  // is not followed). Without a run.json its frames stay: a resume of that run's checkpoint takes up its
  // frames from before the checkpoint, which no run.json lists now.
  const fs::path manifest = dir / kOutputsManifest;
  std::error_code mec;
  if (fs::is_regular_file(fs::symlink_status(manifest, mec))) {
    std::ifstream in(manifest);
    for (std::string line; std::getline(in, line);)
      if (!line.empty() && (old_run || line.rfind("frames/", 0) != 0)) stale.push_back(line);
  }
  // every file is checked before any moves, so a missing one leaves the earlier outputs as they were
  std::vector<std::string> order;
  std::set<std::string> listed;
  for (const std::string& n : names)
    if (listed.insert(n).second) order.push_back(n);
  for (const std::string& n : order) {
    if (!fs::is_regular_file(staging / n))
      throw core::FileError("cannot move '" + n + "' into '" + dir.string() + "': it was not written");
    // nor may anything stand in its place but an earlier file (a folder made there during the run)
    std::error_code ec;
    const fs::path to = dir / n;
    if (fs::exists(to, ec) && !fs::is_regular_file(to, ec))
      throw core::FileError("cannot move '" + n + "' into '" + dir.string() + "': '" + to.string() + "' is " +
                            not_a_file(to) + "; move that away, then resume");
    if (to.parent_path() != dir && fs::exists(fs::symlink_status(to.parent_path(), ec)) &&
        !fs::is_directory(to.parent_path(), ec))  // a file, or a link to nothing
      throw core::FileError("cannot move '" + n + "' into '" + dir.string() + "': '" + to.parent_path().string() +
                            "' is not a folder; move that away, then resume");
  }
  // the old run.json goes first and the new one last: a folder that a kill leaves between two runs' files
  // has no run.json (README: such a folder is unfinished)
  if (listed.count("run.json")) {
    std::stable_partition(order.begin(), order.end(), [](const std::string& n) { return n != "run.json"; });
    // what the old run.json listed, and this run's outputs, outlive it until the commit is whole: a run
    // in a folder a kill left without run.json still cleans up both
    std::set<std::string> both(stale.begin(), stale.end());
    both.insert(order.begin(), order.end());
    try {  // (best effort: a commit without it, into a full disk say, is as it was before the list)
      core::write_file_atomically(manifest, [&](std::ostream& out) {
        for (const std::string& n : both) out << n << '\n';
      });
    } catch (const core::FileError&) {
    }
    std::error_code ec;
    fs::remove(dir / "run.json", ec);
    if (ec && fs::exists(dir / "run.json"))
      throw core::FileError("cannot replace '" + (dir / "run.json").string() + "': " + ec.message());
    core::sync_directory(dir);  // gone before any move lands (a crash never leaves it over a mix)
  }
  for (const std::string& n : order) {
    const fs::path to = dir / n;
    core::ensure_directory(to.parent_path());
    std::error_code ec;
    fs::rename(staging / n, to, ec);
    if (ec) throw core::FileError("cannot move '" + n + "' into '" + dir.string() + "': " + ec.message());
  }
  core::sync_directory(dir);  // the moves reach the disk before the old files go (a crash keeps a whole run)
  std::error_code fec;
  if (fs::is_directory(dir / "frames", fec)) core::sync_directory(dir / "frames");
  for (const std::string& n : stale) {
    if (fresh.count(n) || !own_output(dir, n)) continue;  // only cellform's files, inside dir
    std::error_code ec;
    fs::remove(dir / n, ec);
  }
  std::error_code ec;
  if (listed.count("run.json") && fs::is_regular_file(fs::symlink_status(manifest, ec))) fs::remove(manifest, ec);
  fs::remove_all(staging, ec);
  // frames/ emptied of the earlier run's frames goes too (fs::remove removes only an empty folder)
  if (std::any_of(stale.begin(), stale.end(), [](const std::string& n) { return n.rfind("frames/", 0) == 0; }) &&
      !fs::is_symlink(dir / "frames", ec) && fs::is_directory(dir / "frames", ec))
    fs::remove(dir / "frames", ec);
}

}  // namespace cellform::app
