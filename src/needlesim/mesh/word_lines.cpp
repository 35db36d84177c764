// Line-by-line words of a text surface file (mesh/word_lines.hpp).
#include "needlesim/mesh/word_lines.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <sstream>

#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

WordLines::WordLines(std::string path, const std::string& text, std::string allowed, char comment)
    : path_(std::move(path)), text_(text), allowed_(std::move(allowed)), comment_(comment) {}

bool WordLines::next() {
  while (at_ < text_.size()) {
    std::size_t end = text_.find('\n', at_);
    if (end == std::string::npos) end = text_.size();
    std::string line = text_.substr(at_, end - at_);
    at_ = end + 1;
    ++line_;
    if (comment_ != '\0') line = line.substr(0, line.find(comment_));
    std::istringstream in(line);
    words_.clear();
    for (std::string w; in >> w;) words_.push_back(w);
    if (!words_.empty()) return true;
  }
  words_.clear();
  return false;
}

std::string WordLines::joined() const {
  std::string s;
  for (const auto& w : words_) s += (s.empty() ? "" : " ") + w;
  return s;
}

double WordLines::number(std::size_t i) const {
  char* end = nullptr;
  const double v = std::strtod(words_[i].c_str(), &end);
  if (end == words_[i].c_str() || *end != '\0')
    throw error(fmt::format("has \"{}\" where a number is expected", printable(words_[i])));
  return v;
}

long long WordLines::count(std::size_t i, const std::string& what) const {
  const std::string& w = words_[i];
  if (w.empty() || w.size() > 12 || w.find_first_not_of("0123456789") != std::string::npos)
    throw error(fmt::format("has \"{}\" where {} (a whole number of at least 0) is expected", printable(w), what));
  return std::atoll(w.c_str());
}

InputError WordLines::error(const std::string& problem) const { return error(problem, allowed_); }

InputError WordLines::error(const std::string& problem, const std::string& allowed) const {
  return surfaceError(path_, line_, problem, allowed);
}

}  // namespace needlesim::mesh
