#pragma once
// The output an observer presents into: each dataset is written with its meaning, and the list of
// them — path, shape, meaning, observer — becomes the run's manifest (/manifest, docs/output.md),
// so that a reader can check an output against what its simulator wrote without re-deriving the
// layout from the config.
#include <cstdint>
#include <string>
#include <vector>

#include "granboltz/h5/hdf5_io.hpp"

namespace granboltz {

class Presenter {
 public:
  explicit Presenter(H5Writer& out) : out_(out) {}

  /// The observer whose datasets follow (the manifest's `observer` column).
  void observer(std::string name) { observer_ = std::move(name); }

  void write(const std::string& path, const std::vector<double>& data, const Dims& dims,
             const std::string& meaning);
  void write(const std::string& path, const std::vector<std::uint64_t>& data, const Dims& dims,
             const std::string& meaning);
  void attr(const std::string& object, const std::string& name, const std::string& value) {
    out_.attr(object, name, value);
  }
  void attr(const std::string& object, const std::string& name, double value) {
    out_.attr(object, name, value);
  }
  void attr(const std::string& object, const std::string& name, std::uint64_t value) {
    out_.attr(object, name, value);
  }

  /// /manifest: one row per dataset written so far, in the order written (docs/output.md).
  void write_manifest();

 private:
  struct Entry {
    std::string path, observer, meaning;
    Dims shape;
  };
  void add(const std::string& path, const Dims& dims, const std::string& meaning);
  H5Writer& out_;
  std::string observer_;
  std::vector<Entry> entries_;
};

}  // namespace granboltz
