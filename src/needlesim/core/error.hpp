#pragma once
// Errors that reach the user. Every input problem names where it is (file,
// line, column), which field, the offending value and what is allowed.
#include <stdexcept>
#include <string>

namespace needlesim {

// Base of every error needlesim reports to a user (exit code 2 for input, 3 for solver).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SourceLocation {
  std::string file;  // empty when the input did not come from a file
  int line = 0;      // 1-based; 0 = unknown
  int column = 0;    // 1-based; 0 = unknown
  std::string str() const;
};

// A problem with user input: scenario, data file or argument.
class InputError : public Error {
 public:
  InputError(SourceLocation where, std::string field, std::string value, std::string problem,
             std::string allowed);
  const SourceLocation& where() const { return where_; }
  const std::string& field() const { return field_; }

 private:
  SourceLocation where_;
  std::string field_;
};

// A solver that cannot go on (unstable step, divergence). Says why and what to change.
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace needlesim
