#pragma once
// Files are written atomically: to a temporary file beside the target, then
// renamed, so a crash never leaves a half-written result.
#include <filesystem>
#include <string_view>

namespace needlesim::io {

void writeFileAtomic(const std::filesystem::path& path, std::string_view content);

}  // namespace needlesim::io
