// Which code this program was built from.
#pragma once

namespace stsv {

/// The version of the build: the release version (CMakeLists.txt's project version) when built
/// from a source tarball; in a git checkout the tag's `git describe` ("0.2.0", "0.2.0-3-g1a2b3c4d"),
/// or before any release tag the project version with the commit ("0.1.0+g1a2b3c4d"), with
/// "-dirty" when the tree had uncommitted changes. Written at build time by cmake/Version.cmake.
const char* version();

} // namespace stsv
