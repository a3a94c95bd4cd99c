// The `stsv` subcommands. Argument parsing lives here and only here; every command returns a
// process exit code and reports errors as one line on stderr.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace stsv {

/// Runs the command line (argv without the program name is parsed by CLI11). Never throws.
int runCli(int argc, char** argv);

/// Runs `command` and maps what escapes it to the exit status and one line on stderr: a
/// stsv::Error (bad input, usage) "stsv: error: …" and 1; running out of memory the message naming
/// the memory limit and 1; any other exception "stsv: internal error: …" and 2 (a bug).
int runReportingErrors(const std::function<int()>& command);

/// Parses "WxH" (e.g. "512x512"); throws UsageError on anything else.
void parseSize(const std::string& text, int& width, int& height);

/// Path for the output of light `light` of several: `path` itself for light 0, and
/// "stem_light<i>.ext" for the others.
std::string perLightPath(const std::string& path, std::size_t light);

} // namespace stsv
