// Typed exceptions with context (DESIGN §7). Library code throws; only cli/ exits.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace stsv {

/// Base of every error stsv throws; what() is one line a user can act on.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Bad input: a file (and, where known, a line of it) and what is wrong with it.
class InputError : public Error {
  public:
    InputError(const std::string& file, std::size_t line, const std::string& problem);
    InputError(const std::string& file, const std::string& problem);

    const std::string& file() const { return m_file; }
    std::size_t line() const { return m_line; } ///< 0 when the problem is not on one line

  private:
    std::string m_file;
    std::size_t m_line = 0;
};

/// A request the program cannot satisfy (absurd sizes, unknown names, bad option values).
class UsageError : public Error {
  public:
    using Error::Error;
};

} // namespace stsv
