#pragma once
// Files are written atomically: to a temporary file beside the target, then
// renamed, so a crash never leaves a half-written result. A write that fails
// (disk full, file size limit, I/O error) is an Error naming the file.
#include <filesystem>
#include <string_view>

namespace needlesim::io {

void writeFileAtomic(const std::filesystem::path& path, std::string_view content);

// Throws Error("cannot write <path>: disk full / write failed: <errno text>")
// (for ENOSPC, EFBIG, EDQUOT; "write failed: <errno text>" for others): the
// one message for every failed write of a results or checkpoint file.
[[noreturn]] void throwWriteFailure(const std::filesystem::path& path, int errnum);

}  // namespace needlesim::io
