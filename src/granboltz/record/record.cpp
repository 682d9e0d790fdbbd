#include "granboltz/record/record.hpp"

#include <stdexcept>

namespace granboltz {

namespace {
thread_local Record::Sizing* sizing = nullptr;
}  // namespace

Record::Sizing::Sizing() : previous_(sizing) { sizing = this; }
Record::Sizing::~Sizing() { sizing = previous_; }

void Record::declare_moments(const std::string& name, std::size_t size) {
  if (sizing) {
    sizing->moments += size;
    return;
  }
  moments_[name].assign(size, Moments2{});
}

void Record::declare_counts(const std::string& name, std::size_t size) {
  if (sizing) {
    sizing->counts += size;
    return;
  }
  counts_[name] = Counts{std::vector<std::uint64_t>(size, 0), std::vector<uint128>(size, 0)};
}

void Record::declare_total(const std::string& name) { totals_[name] = 0; }

void Record::declare_column(const std::string& path, bool floating) {
  columns_.push_back({path, floating});
}

void Record::add_counts(const std::string& name, const std::vector<std::uint64_t>& c) {
  Counts& k = counts_.at(name);
  if (c.size() != k.sum.size()) throw std::logic_error("Record: wrong count size for " + name);
  for (std::size_t i = 0; i < c.size(); ++i) {
    k.sum[i] += c[i];
    k.sum_sq[i] += static_cast<uint128>(c[i]) * c[i];
  }
}

const std::vector<std::uint64_t>& Record::counts(const std::string& name) const {
  return counts_.at(name).sum;
}
const std::vector<uint128>& Record::counts_sq(const std::string& name) const {
  return counts_.at(name).sum_sq;
}

void Record::add_ensemble(std::uint64_t e, const std::vector<double>& values) {
  if (values.size() != columns_.size()) throw std::logic_error("Record: wrong number of columns");
  if (!rows_.emplace(e, values).second)
    throw std::runtime_error("ensemble " + std::to_string(e) + " is present twice");
}

std::vector<std::uint64_t> Record::ensemble_indices() const {
  std::vector<std::uint64_t> out;
  out.reserve(rows_.size());
  for (const auto& kv : rows_) out.push_back(kv.first);
  return out;
}

std::vector<double> Record::column(const std::string& path) const {
  std::size_t c = 0;
  while (c < columns_.size() && columns_[c].path != path) ++c;
  if (c == columns_.size()) throw std::logic_error("Record: no column " + path);
  std::vector<double> out;
  out.reserve(rows_.size());
  for (const auto& kv : rows_) out.push_back(kv.second[c]);
  return out;
}

void Record::merge(const Record& o) {
  for (const auto& kv : o.rows_)
    if (rows_.count(kv.first))
      throw std::runtime_error("ensemble " + std::to_string(kv.first) +
                               " is in more than one input (overlapping shards)");
  for (auto& [name, sums] : moments_) {
    const auto& other = o.moments_.at(name);
    if (other.size() != sums.size()) throw std::runtime_error("different layouts of " + name);
    for (std::size_t i = 0; i < sums.size(); ++i) sums[i].merge(other[i]);
  }
  for (auto& [name, k] : counts_) {
    const Counts& other = o.counts_.at(name);
    if (other.sum.size() != k.sum.size()) throw std::runtime_error("different layouts of " + name);
    for (std::size_t i = 0; i < k.sum.size(); ++i) {
      k.sum[i] += other.sum[i];
      k.sum_sq[i] += other.sum_sq[i];
    }
  }
  for (auto& [name, t] : totals_) t += o.totals_.at(name);
  for (const auto& kv : o.rows_) rows_.insert(kv);
}

void Record::write(H5Writer& out) const {
  out.group("/accumulators");
  for (const auto& [name, sums] : moments_) {
    std::vector<std::int64_t> digits;
    digits.reserve(sums.size() * 2 * ExactSum::kLimbs);
    for (const auto& m : sums)
      for (const ExactSum* e : {&m.sum, &m.sum_sq}) {
        const auto d = e->digits();
        digits.insert(digits.end(), d.begin(), d.end());
      }
    out.write("/accumulators/" + name, digits,
              {sums.size(), 2, static_cast<hsize_t>(ExactSum::kLimbs)});
  }
  for (const auto& [name, k] : counts_) {
    out.write("/accumulators/" + name, k.sum, {k.sum.size()});
    std::vector<std::uint64_t> sq(2 * k.sum_sq.size());
    for (std::size_t i = 0; i < k.sum_sq.size(); ++i) {
      sq[2 * i] = static_cast<std::uint64_t>(k.sum_sq[i] >> 64);
      sq[2 * i + 1] = static_cast<std::uint64_t>(k.sum_sq[i]);
    }
    out.write("/accumulators/" + name + "_sq", sq, {k.sum_sq.size(), 2});
  }
  for (const auto& [name, t] : totals_) out.attr("/accumulators", name, t);
  const std::size_t N = rows_.size();
  out.write("/events/ensemble", ensemble_indices(), {N});
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    const std::vector<double> v = column(columns_[c].path);
    if (columns_[c].floating) {
      out.write(columns_[c].path, v, {N});
    } else {
      std::vector<std::uint64_t> u(N);
      for (std::size_t i = 0; i < N; ++i) u[i] = static_cast<std::uint64_t>(v[i]);
      out.write(columns_[c].path, u, {N});
    }
  }
}

void Record::read(const H5Reader& in) {
  for (auto& [name, sums] : moments_) {
    const std::string path = "/accumulators/" + name;
    const auto dims = in.dims(path);
    if (dims != Dims{sums.size(), 2, static_cast<hsize_t>(ExactSum::kLimbs)})
      throw std::runtime_error(in.path() + ": " + path + " has the wrong shape for this config");
    const auto digits = in.read_int64(path);
    const std::size_t L = ExactSum::kLimbs;
    for (std::size_t i = 0; i < sums.size(); ++i) {
      auto at = digits.begin() + static_cast<std::ptrdiff_t>(2 * i * L);
      sums[i].sum = ExactSum::from_digits({at, at + static_cast<std::ptrdiff_t>(L)});
      sums[i].sum_sq = ExactSum::from_digits(
          {at + static_cast<std::ptrdiff_t>(L), at + static_cast<std::ptrdiff_t>(2 * L)});
    }
  }
  for (auto& [name, k] : counts_) {
    const std::string path = "/accumulators/" + name;
    if (in.dims(path) != Dims{k.sum.size()} || in.dims(path + "_sq") != Dims{k.sum.size(), 2})
      throw std::runtime_error(in.path() + ": " + path + " has the wrong shape for this config");
    k.sum = in.read_uint64(path);
    const auto sq = in.read_uint64(path + "_sq");
    for (std::size_t i = 0; i < k.sum.size(); ++i)
      k.sum_sq[i] = (static_cast<uint128>(sq[2 * i]) << 64) | sq[2 * i + 1];
  }
  for (auto& [name, t] : totals_) t = in.attr_uint64("/accumulators", name);
  const auto index = in.read_uint64("/events/ensemble");
  std::vector<std::vector<double>> cols;
  for (const auto& c : columns_) {
    if (in.dims(c.path) != Dims{index.size()})
      throw std::runtime_error(in.path() + ": " + c.path + " does not match /events/ensemble");
    if (c.floating) {
      cols.push_back(in.read_double(c.path));
    } else {
      const auto u = in.read_uint64(c.path);
      cols.emplace_back(u.begin(), u.end());
    }
  }
  rows_.clear();
  for (std::size_t i = 0; i < index.size(); ++i) {
    std::vector<double> row(columns_.size());
    for (std::size_t c = 0; c < columns_.size(); ++c) row[c] = cols[c][i];
    add_ensemble(index[i], row);
  }
}

}  // namespace granboltz
