#include "needlesim/core/error.hpp"

#include <fmt/format.h>

namespace needlesim {

std::string SourceLocation::str() const {
  std::string s = file.empty() ? std::string("<input>") : printable(file, 4 * kEchoChars);
  if (line > 0) s += fmt::format(":{}", line);
  if (line > 0 && column > 0) s += fmt::format(":{}", column);
  return s;
}

namespace {

// Length of the well-formed UTF-8 character starting at s[i] (2 to 4 bytes), or 0.
std::size_t utf8SequenceLength(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;  // no overlong forms
    if (c == 0xED) hi = 0x9F;  // no surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;  // nothing above U+10FFFF
  } else {
    return 0;
  }
  if (i + n > s.size() || b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  return n;
}

std::string escaped(unsigned char c) {
  switch (c) {
    case '\n': return "\\n";
    case '\r': return "\\r";
    case '\t': return "\\t";
    default: return fmt::format("\\x{:02x}", c);
  }
}

std::string compose(const SourceLocation& where, const std::string& field, const std::string& value,
                    const std::string& problem, const std::string& allowed) {
  // The problem and what is allowed may quote a nested message; they are escaped, and cut
  // only where they would flood a terminal.
  constexpr std::size_t kLongText = 4000;
  std::string msg = where.str() + ": ";
  if (!field.empty()) msg += printable(field, 2 * kEchoChars) + ": ";
  msg += printable(problem, kLongText);
  if (!value.empty()) msg += fmt::format(" (got '{}')", printable(value));
  if (!allowed.empty()) msg += "; allowed: " + printable(allowed, kLongText);
  return msg;
}

}  // namespace

std::size_t utf8ErrorOffset(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    const std::size_t n = utf8SequenceLength(text, i);
    if (n == 0) return i;
    i += n;
  }
  return std::string_view::npos;
}

std::string printable(std::string_view text, std::size_t max_chars) {
  std::string out;
  std::size_t chars = 0, i = 0;
  while (i < text.size() && chars < max_chars) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = c < 0x80 ? 1 : utf8SequenceLength(text, i);
    // C0 and C1 control characters (U+0080-U+009F, e.g. the one-byte CSI) steer terminals.
    const bool c1 = n == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0;
    if (c < 0x20 || c == 0x7F || n == 0 || c1) {
      out += escaped(c);
      ++i;
    } else {
      out.append(text.substr(i, n));
      i += n;
    }
    ++chars;
  }
  if (i < text.size()) out += fmt::format("... ({} bytes)", text.size());
  return out;
}

InputError::InputError(SourceLocation where, std::string field, std::string value,
                       std::string problem, std::string allowed)
    : Error(compose(where, field, value, problem, allowed)),
      where_(std::move(where)),
      field_(std::move(field)) {}

InputError::InputError(Composed, SourceLocation where, std::string field, std::string message)
    : Error(std::move(message)), where_(std::move(where)), field_(std::move(field)) {}

InputError InputError::withMessage(SourceLocation where, std::string field, std::string message) {
  return InputError(Composed{}, std::move(where), std::move(field), std::move(message));
}

}  // namespace needlesim
