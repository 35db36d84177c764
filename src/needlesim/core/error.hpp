#pragma once
// Errors that reach the user. Every input problem names where it is (file,
// line, column), which field, the offending value and what is allowed.
#include <stdexcept>
#include <string>
#include <string_view>

namespace needlesim {

// Base of every error needlesim reports to a user (exit code 2 for input, 3 for solver).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// How many characters of an offending value an error message echoes.
inline constexpr std::size_t kEchoChars = 60;

struct SourceLocation {
  std::string file;  // empty when the input did not come from a file
  int line = 0;      // 1-based; 0 = unknown
  int column = 0;    // 1-based; 0 = unknown
  std::string str() const;
};

// Where a command-line argument's error is: the command line itself.
inline SourceLocation commandLine() { return SourceLocation{"command line", 0, 0}; }

// `text` as it may be shown on a terminal: control bytes and bytes that are not UTF-8 are
// escaped (\x1b, \n), and text longer than `max_chars` characters is cut there and ends with
// "... (N bytes)". Every InputError message passes its parts through this.
std::string printable(std::string_view text, std::size_t max_chars = kEchoChars);

// Byte offset of the first byte of `text` that is not part of a well-formed UTF-8
// character, or std::string_view::npos when all of it is UTF-8.
std::size_t utf8ErrorOffset(std::string_view text);

// A problem with user input: scenario, data file or argument.
class InputError : public Error {
 public:
  InputError(SourceLocation where, std::string field, std::string value, std::string problem,
             std::string allowed);
  const SourceLocation& where() const { return where_; }
  const std::string& field() const { return field_; }
  // The same error with its message as composed before (an error handed back by another process).
  static InputError withMessage(SourceLocation where, std::string field, std::string message);

 private:
  struct Composed {};
  InputError(Composed, SourceLocation where, std::string field, std::string message);
  SourceLocation where_;
  std::string field_;
};

// A solver that cannot go on (unstable step, divergence). Says why and what to change.
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace needlesim
