#pragma once
// Minimal HDF5 output and input. An output file is built in memory, written under a temporary
// name and renamed into place only when complete, so that an interrupted run or a full disk never
// leaves a file that looks done. Every dataset is checksummed (Fletcher32 on chunks; scalars by
// their object header's checksum) and a reader names the file and dataset whose check fails.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace granboltz {

using Dims = std::vector<hsize_t>;

class H5Writer {
 public:
  /// Creates `path`.tmp.<pid>; throws std::runtime_error naming the path if it cannot.
  explicit H5Writer(const std::string& path);
  ~H5Writer();  ///< removes the temporary file unless commit() succeeded
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  /// Datasets by absolute path ("/temperature/mean"); intermediate groups are created.
  void write(const std::string& path, const std::vector<double>& data, const Dims& dims);
  void write(const std::string& path, const std::vector<std::uint64_t>& data, const Dims& dims);
  void write(const std::string& path, const std::vector<std::int64_t>& data, const Dims& dims);
  void group(const std::string& path);
  /// Attributes of an existing object ("/" for the root).
  void attr(const std::string& object, const std::string& name, const std::string& value);
  void attr(const std::string& object, const std::string& name, double value);
  void attr(const std::string& object, const std::string& name, std::uint64_t value);

  /// Writes the file to disk and renames it to its final path; on any error (full disk, size
  /// limit) removes the temporary file and throws a one-line message naming the path.
  void commit();
  const std::string& temp_path() const { return tmp_; }

 private:
  void write_raw(const std::string& path, hid_t mem_type, hid_t file_type, const void* data,
                 const Dims& dims);
  void discard();  // closes everything and removes the temporary file
  std::string path_, tmp_;
  hid_t file_ = -1;
  int fd_ = -1;  // the temporary file, created at once so that a bad path fails early
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

 private:
  void read_raw(const std::string& path, hid_t mem_type, void* out, std::size_t count) const;
  hid_t open_dataset(const std::string& path) const;  // throws naming a checksum mismatch
  void read_checked(hid_t ds, const std::string& path, hid_t mem_type, void* out) const;
  std::string path_;
  hid_t file_ = -1;
};

}  // namespace granboltz
