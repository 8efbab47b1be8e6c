// Saving rig and show files the way an editor must: atomically (a temporary file beside the
// file, flushed to disk, then renamed over it — a crash or a full disk leaves the old file or
// the new one, never half of one), keeping the file's permissions, writing through a symbolic
// link to the file it names, and keeping the text a person wrote (appends add to it as it is).
#pragma once

#include <string>

namespace mar {

/// Replaces the file at `path` with `text`. Returns an error message naming the file, or "".
std::string write_atomically(const std::string& path, const std::string& text);

/// Adds `text` after the file's text as it is (comments, order, spacing). Returns an error
/// message naming the file, or "".
std::string append_atomically(const std::string& path, const std::string& text);

}  // namespace mar
