// Small helpers shared by the backends: files in sysfs, text for identities.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "devices/discover.h"

namespace mar::devutil {

/// Whole file as bytes (sysfs attributes, descriptors); empty when unreadable.
std::vector<uint8_t> read_file(const std::string& path);
/// First line of a text file, trimmed; empty when unreadable.
std::string read_line(const std::string& path);
bool exists(const std::string& path);
/// "054c:09cc"
std::string vid_pid(int vid, int pid);
/// Wide string (hidapi) to UTF-8 for ASCII text; other characters become '?'.
std::string narrow(const wchar_t* w);
/// Entries of a directory (names only, sorted); empty when missing.
std::vector<std::string> list_dir(const std::string& path);

/// The profile (config/devices) that names vid:pid; empty when none does.
std::string profile_of(const std::vector<ProfileId>& profiles, int vid, int pid);
/// "available", or "permission denied" with the udev hint, for f.node.
void access_status(FoundDevice& f);

}  // namespace mar::devutil
