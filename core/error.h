// Typed exceptions with context (DESIGN §7). Library code throws; only cli/ exits.
#pragma once

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>

namespace stsv {

/// Base of every error stsv throws; message() is one line a user can act on.
class Error : public std::runtime_error {
  public:
    explicit Error(const std::string& message)
        : std::runtime_error(message), m_message(std::make_shared<const std::string>(message)) {}
    explicit Error(const char* message) : Error(std::string(message)) {}

    /// The whole message. A message may quote input that holds a NUL byte (a JSON string value
    /// "\u0000", a file name read from a scene), where what(), a C string, would end: print this
    /// one, through printable().
    const std::string& message() const { return *m_message; }

  private:
    std::shared_ptr<const std::string> m_message; ///< shared: copying an exception cannot throw
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

/// Text as a terminal should show it: control bytes (NUL included) and bytes that are not valid
/// UTF-8 (a garbage file's contents quoted by a loader) as \xNN escapes, at most `maxLength`
/// characters and then "..." (a loader may quote a megabyte-long token). Everything stsv prints
/// that holds input (messages, warnings, file names) goes through it.
std::string printable(const std::string& text, std::size_t maxLength = 400);

} // namespace stsv
