#pragma once
// The text surface formats (ASCII STL, OFF) read line by line as words: blank lines skipped,
// comments cut, numbers and counts parsed strictly, and every error naming the file and line.
#include <cstddef>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"

namespace needlesim::mesh {

class WordLines {
 public:
  // `comment`: the character that starts a comment to the end of the line ('\0': none).
  WordLines(std::string path, const std::string& text, std::string allowed, char comment = '\0');

  bool next();  // the next line with words on it; false at the end of the text
  const std::vector<std::string>& words() const { return words_; }
  int line() const { return line_; }
  std::size_t bytesLeft() const { return text_.size() - std::min(at_, text_.size()); }
  std::string joined() const;  // the line's words, one space apart
  double number(std::size_t i) const;  // word i as a number, else an error
  long long count(std::size_t i, const std::string& what) const;  // word i as a whole number >= 0
  InputError error(const std::string& problem) const;  // path:line, the format's allowed text
  InputError error(const std::string& problem, const std::string& allowed) const;

 private:
  std::string path_;
  const std::string& text_;
  std::string allowed_;
  char comment_;
  std::size_t at_ = 0;
  int line_ = 0;
  std::vector<std::string> words_;
};

}  // namespace needlesim::mesh
