// Files that appear complete or not at all: write to a temporary name, rename when done.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace cellform::core {

/// Writes `path` through `write` into a temporary file beside it, flushes, fsyncs and renames it over
/// `path`, then syncs the folder. On any failure (an unwritable directory, a full disk, an exception from `write`) the
/// temporary file is removed, `path` is left as it was, and FileError names the path and the cause.
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// Flushes `dir`'s entries (the names renamed or removed in it) to disk, so that a crash of the machine
/// cannot undo them. Best effort: a folder that cannot be opened or synced is left as it is.
void sync_directory(const std::filesystem::path& dir);

/// Creates `dir` and its parents if needed; FileError if it exists and is not a directory or cannot be made.
void ensure_directory(const std::filesystem::path& dir);
/// The same, setting `ec` instead of throwing (std::errc::not_a_directory if `dir` is something else).
void ensure_directory(const std::filesystem::path& dir, std::error_code& ec);

/// Reads a whole file; FileError naming the path if it is missing or unreadable.
std::string read_file(const std::filesystem::path& path);

}  // namespace cellform::core
