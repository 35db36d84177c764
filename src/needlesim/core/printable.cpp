#include "needlesim/core/printable.hpp"

#include <fmt/format.h>

namespace needlesim {

std::string printableText(const std::string& s, std::size_t limit) {
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < limit; ++i) {
    auto c = static_cast<unsigned char>(s[i]);
    out += (c >= 0x20 && c < 0x7f) ? std::string(1, s[i]) : fmt::format("\\x{:02X}", c);
  }
  if (s.size() > limit) out += fmt::format("... ({} characters)", s.size());
  return out;
}

}  // namespace needlesim
