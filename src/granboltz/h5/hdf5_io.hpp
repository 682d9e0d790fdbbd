#pragma once
// Minimal HDF5 output and input. An output file is built in memory, written under a temporary
// name and renamed into place only when complete, so that an interrupted run or a full disk never
// leaves a file that looks done. Every dataset is checksummed (Fletcher32 on chunks; scalars by
// their object header's checksum) and a reader names the file and dataset whose check fails.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace granboltz {

using Dims = std::vector<hsize_t>;

/// Refuses, before any work, an output path that must not be written: one that exists and is not
/// a regular file (a FIFO, a device, a symbolic link, a directory), whose directory does not
/// exist, or that is one of `inputs` by device and inode (a hard link or another spelling of a
/// config, shard or checkpoint the run reads). Throws std::runtime_error naming the path.
void check_output_path(const std::string& path, const std::vector<std::string>& inputs = {});

/// Refuses an input that is not a regular file (a FIFO would block the reader, a device would be
/// read without end); throws std::runtime_error naming the path. Follows symbolic links.
void check_input_file(const std::string& path, const std::string& what);

/// Removes every temporary file that an H5Writer of this process has open. Async-signal-safe:
/// for signal handlers, which then end the process.
void remove_temporaries_now() noexcept;

/// Turns HDF5's automatic printing of its error stack off for the calling thread (the setting is
/// per thread in a thread-safe HDF5); every H5Reader and H5Writer calls it.
void silence_hdf5_errors();

class H5Writer {
 public:
  /// Checks `path` (check_output_path without inputs), creates a fresh temporary file beside it
  /// (`path`.tmp.<pid>.<random>, never following or replacing an existing name) and takes an
  /// exclusive advisory lock on it, held until the file is in place. Temporary files of the same
  /// output left by processes that died are removed; one that another process holds locked means
  /// a second run on the same output, which is refused. Throws std::runtime_error naming the path.
  explicit H5Writer(const std::string& path);
  ~H5Writer();  ///< removes the temporary file unless commit() succeeded
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  /// Datasets by absolute path ("/temperature/mean"); intermediate groups are created.
  void write(const std::string& path, const std::vector<double>& data, const Dims& dims);
  void write(const std::string& path, const std::vector<std::uint64_t>& data, const Dims& dims);
  void write(const std::string& path, const std::vector<std::int64_t>& data, const Dims& dims);
  /// Text as a 1-D dataset of fixed-length UTF-8 strings (null-padded to the longest): fixed
  /// bytes, so that the digest covers it as any other dataset.
  void write(const std::string& path, const std::vector<std::string>& data);
  void group(const std::string& path);
  /// Attributes of an existing object ("/" for the root).
  void attr(const std::string& object, const std::string& name, const std::string& value);
  void attr(const std::string& object, const std::string& name, double value);
  void attr(const std::string& object, const std::string& name, std::uint64_t value);

  /// Writes the file to disk and renames it to its final path; on any error (full disk, size
  /// limit) removes the temporary file and throws a one-line message naming the path.
  void commit();
  const std::string& temp_path() const { return tmp_; }
  /// A hash of every dataset written so far (path, type, shape and bytes, in path order), equal
  /// to H5Reader::digest of the finished file: a checkpoint stores it, so that an edited
  /// checkpoint is refused even though HDF5 recomputed its checksums.
  std::uint64_t digest() const;

 private:
  void write_raw(const std::string& path, hid_t mem_type, hid_t file_type, const void* data,
                 const Dims& dims);
  void discard();  // closes everything and removes the temporary file
  std::string path_, tmp_;
  hid_t file_ = -1;
  int fd_ = -1;    // the temporary file, created at once so that a bad path fails early
  int slot_ = -1;  // its entry in the registry of temporary files (remove_temporaries_now)
  std::vector<std::pair<std::string, std::uint64_t>> digests_;  // dataset path, content hash
};

class H5Reader {
 public:
  explicit H5Reader(const std::string& path);  ///< throws naming the path if not HDF5
  ~H5Reader();
  H5Reader(const H5Reader&) = delete;
  H5Reader& operator=(const H5Reader&) = delete;

  bool exists(const std::string& path) const;
  Dims dims(const std::string& path) const;
  std::vector<double> read_double(const std::string& path) const;
  std::vector<std::uint64_t> read_uint64(const std::string& path) const;
  std::vector<std::int64_t> read_int64(const std::string& path) const;
  /// The stored bytes of a dataset in its own type, for bit-for-bit comparisons.
  std::vector<unsigned char> read_bytes(const std::string& path) const;
  std::string attr_string(const std::string& object, const std::string& name) const;
  std::uint64_t attr_uint64(const std::string& object, const std::string& name) const;
  bool has_attr(const std::string& object, const std::string& name) const;
  const std::string& path() const { return path_; }
  /// Absolute paths of all datasets, in name order.
  std::vector<std::string> datasets() const;
  /// Reads every dataset in full (so that HDF5 checks every chunk's Fletcher32 and every object
  /// header's checksum) and returns one line per dataset that fails ("/a/b: checksum mismatch"),
  /// empty when the file is sound.
  std::vector<std::string> damaged() const;
  /// The hash of all datasets that H5Writer::digest gives for the same content.
  std::uint64_t digest() const;

 private:
  void read_raw(const std::string& path, hid_t mem_type, void* out, std::size_t count) const;
  hid_t open_dataset(const std::string& path) const;  // throws naming a checksum mismatch
  void read_checked(hid_t ds, const std::string& path, hid_t mem_type, void* out) const;
  std::string path_;
  hid_t file_ = -1;
};

}  // namespace granboltz
