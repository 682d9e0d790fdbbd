#pragma once
// Checking granboltz files without trusting them: every dataset read in full, so that HDF5
// checks each chunk's Fletcher32 and each object header's checksum; a checkpoint also against
// the digest of its datasets that it stores (which an edit with HDF5 itself does not update).
#include <ostream>
#include <string>
#include <vector>

namespace granboltz {

/// What is wrong with one file, one line each ("/events/kicks: checksum mismatch ..."); empty
/// when every dataset reads back sound. A file that does not open gives one line saying why.
std::vector<std::string> file_problems(const std::string& path);

/// `granboltz verify`: one line per file on `out` ("FILE: ok, 42 datasets") or per problem on
/// `err` ("FILE: damaged: ..."); true if every file is sound.
bool verify_files(const std::vector<std::string>& paths, std::ostream& out, std::ostream& err);

}  // namespace granboltz
