#include "core/error.h"

namespace stsv {

InputError::InputError(const std::string& file, std::size_t line, const std::string& problem)
    : Error(file + ":" + std::to_string(line) + ": " + problem), m_file(file), m_line(line) {}

InputError::InputError(const std::string& file, const std::string& problem)
    : Error(file + ": " + problem), m_file(file) {}

} // namespace stsv
