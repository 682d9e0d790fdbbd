#pragma once
// Checking granboltz files without trusting them: every dataset read in full, so that HDF5
// checks each chunk's Fletcher32 and each object header's checksum; then against the digest of
// its datasets that the file stores (every checkpoint, and outputs of this version), which an
// edit with HDF5 itself does not update and which sees what Fletcher32 cannot (0x0000 against
// 0xFFFF words).
#include <ostream>
#include <string>
#include <vector>

namespace granboltz {

struct FileCheck {
  std::vector<std::string> problems;  ///< one line each; empty when the file is sound
  std::size_t datasets = 0;
};

/// Every dataset and attribute of `path` read back and checked (and its digest, where it has
/// one), in a child process: a crash of the HDF5 library on a damaged file is reported as a
/// problem, not suffered.
FileCheck check_file(const std::string& path);

/// What is wrong with one file, one line each ("/events/kicks: checksum mismatch ..."); empty
/// when every dataset reads back sound. A file that does not open gives one line saying why.
std::vector<std::string> file_problems(const std::string& path);

/// `granboltz verify`: one line per file on `out` ("FILE: ok, 42 datasets") or per problem on
/// `err` ("FILE: damaged: ..."); true if every file is sound.
bool verify_files(const std::vector<std::string>& paths, std::ostream& out, std::ostream& err);

}  // namespace granboltz
