#include "granboltz/dsmc/observers/presenter.hpp"

#include <algorithm>

namespace granboltz {

void Presenter::add(const std::string& path, const Dims& dims, const std::string& meaning) {
  entries_.push_back({path, observer_, meaning, dims});
}

void Presenter::write(const std::string& path, const std::vector<double>& data, const Dims& dims,
                      const std::string& meaning) {
  out_.write(path, data, dims);
  add(path, dims, meaning);
}

void Presenter::write(const std::string& path, const std::vector<std::uint64_t>& data,
                      const Dims& dims, const std::string& meaning) {
  out_.write(path, data, dims);
  add(path, dims, meaning);
}

void Presenter::write_manifest() {
  // Parallel columns of one row per dataset: h5py reads each as one array. The shapes are padded
  // with zeros to the largest rank; `rank` says how many of a row's entries count.
  std::size_t width = 1;
  for (const Entry& e : entries_) width = std::max(width, e.shape.size());
  std::vector<std::string> path, observer, meaning;
  std::vector<std::uint64_t> rank, shape(entries_.size() * width, 0);
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    const Entry& e = entries_[k];
    path.push_back(e.path);
    observer.push_back(e.observer);
    meaning.push_back(e.meaning);
    rank.push_back(e.shape.size());
    std::copy(e.shape.begin(), e.shape.end(),
              shape.begin() + static_cast<std::ptrdiff_t>(k * width));
  }
  out_.write("/manifest/path", path);
  out_.write("/manifest/observer", observer);
  out_.write("/manifest/meaning", meaning);
  out_.write("/manifest/rank", rank, {rank.size()});
  out_.write("/manifest/shape", shape, {entries_.size(), width});
  out_.attr("/manifest", "version", std::uint64_t{1});
  out_.attr("/manifest", "description",
            std::string("one row per dataset the run presents: path, shape[:rank], meaning and the "
                        "observer that wrote it (docs/output.md)"));
}

}  // namespace granboltz
