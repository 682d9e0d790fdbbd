#pragma once
// One state archive for the engines' checkpoints. An engine declares its state once, in a member
// function visit_state(StateArchive& a): each dataset by its name under the engine's group, the
// members it holds and the values each may take. Made with a writer, the archive writes the
// datasets; made with a reader, it reads them back into the members and refuses a dataset that
// is missing, of another shape or type, or a value outside its range, in one line naming the
// file, the dataset (and element) and what is allowed: an edited file is refused where it is read,
// not met later as a crash (an index out of range), a hang (a time that never reaches t_end) or
// other numbers.
//
// A packed dataset (pack: /scalars of the time, the bulk velocity, ...) keeps its fields in the
// order declared, so the layout of a checkpoint is the order of the declarations.
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "granboltz/config/reader.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/random/index_stream.hpp"
#include "granboltz/random/rng.hpp"

namespace granboltz {

/// The values a field may take: lo to hi, each end closed or open, the upper named in messages
/// ("t_end"); a double must be finite besides.
template <class T>
struct Range {
  static constexpr T kMin = std::numeric_limits<T>::lowest(), kMax = std::numeric_limits<T>::max();
  T lo = kMin, hi = kMax;
  std::string hi_name, note;  // note: why a range is narrow ("in dimension 2")
  bool lo_open = false, hi_open = false;

  Range() = default;
  Range(T l, T h, std::string name = "", std::string why = "", bool l_open = false,
        bool h_open = false)
      : lo(l),
        hi(h),
        hi_name(std::move(name)),
        note(std::move(why)),
        lo_open(l_open),
        hi_open(h_open) {}
  bool contains(T x) const {
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(x)) return false;
    return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  }
  static std::string show(T x) {
    if constexpr (std::is_floating_point_v<T>)
      return format_real(x);
    else
      return std::to_string(x);
  }
  /// "in [0, t_end = 2]", ">= 0", "0 in dimension 2", "finite"
  std::string text() const {
    const bool high = hi != kMax, low = lo != kMin || (high && std::is_unsigned_v<T>);
    std::string s = std::is_floating_point_v<T> ? "finite" : "any";
    if (low && high && lo == hi)
      s = show(lo);
    else if (low && high)
      s = std::string("in ") + (lo_open ? "(" : "[") + show(lo) + ", " +
          (hi_name.empty() ? "" : hi_name + " = ") + show(hi) + (hi_open ? ")" : "]");
    else if (low)
      s = (lo_open ? "> " : ">= ") + show(lo);
    return note.empty() ? s : s + " " + note;
  }
};

using Real = Range<double>;
using Count = Range<std::uint64_t>;
inline Real finite() { return {}; }
inline Real at_least(double lo) { return {lo, Real::kMax}; }
inline Real positive() { return {0.0, Real::kMax, "", "", true}; }
inline Real within(double lo, double hi, std::string hi_name = "") {
  return {lo, hi, std::move(hi_name)};
}
/// 0 where `zero` holds (v_z in dimension 2: `why` says so), finite elsewhere.
inline Real zero_if(bool zero, std::string why) {
  return zero ? Real{0.0, 0.0, "", std::move(why)} : finite();
}
/// An index: [0, n).
inline Count below(std::uint64_t n, std::string name) {
  return {0, n, std::move(name), "", false, true};
}
inline Count up_to(std::uint64_t n, std::string name) { return {0, n, std::move(name)}; }
inline Count counts_between(std::uint64_t lo, std::uint64_t hi, std::string hi_name = "") {
  return {lo, hi, std::move(hi_name)};
}

/// One field of a packed dataset: its name in messages, the member and its range.
template <class T, class M>
struct Field {
  const char* name;
  M& value;
  Range<T> range;
};
template <class M>
Field<double, M> real(const char* name, M& value, Real range = {}) {
  return {name, value, std::move(range)};
}
template <class M>
Field<std::uint64_t, M> word(const char* name, M& value, Count range = {}) {
  return {name, value, std::move(range)};
}

/// Writes (made with an H5Writer) or reads (with an H5Reader) the datasets visit_state declares
/// under `group`; the reader stores each value in its member once it is checked.
class StateArchive {
 public:
  StateArchive(H5Writer& out, std::string group) : out_(&out), g_(std::move(group)) {}
  StateArchive(const H5Reader& in, std::string group) : in_(&in), g_(std::move(group)) {}
  bool reading() const { return in_ != nullptr; }

  /// One dataset of the fields f, in their order.
  template <class T, class... M>
  void pack(const std::string& name, const Field<T, M>&... f) {
    if (!in_)
      return out_->write(g_ + "/" + name, std::vector<T>{static_cast<T>(f.value)...},
                         {sizeof...(M)});
    const std::vector<T> v = read<T>(name, {sizeof...(M)});
    std::size_t k = 0;
    ((check(name + "[" + std::to_string(k) + "] (" + f.name + ")", v[k], f.range),
      f.value = static_cast<M>(v[k]), ++k),
     ...);
  }
  /// rows x cols values (cols = 0: a vector), get(i, k) the value of row i, column k; read back,
  /// column k is checked against ranges[k] (ranges[0] for all if it is the only one) and stored
  /// by set(i, k, value).
  template <class T, class Get, class Set>
  void table(const std::string& name, std::size_t rows, std::size_t cols,
             const std::vector<Range<T>>& ranges, Get get, Set set) {
    const std::size_t w = cols ? cols : 1;
    const Dims dims = cols ? Dims{rows, cols} : Dims{rows};
    std::vector<T> v;
    if (!in_) {
      for (std::size_t i = 0; i < rows * w; ++i) v.push_back(get(i / w, i % w));
      return out_->write(g_ + "/" + name, v, dims);
    }
    v = read<T>(name, dims);
    for (std::size_t i = 0; i < rows * w; ++i)
      check(name + "[" + std::to_string(i / w) + (cols ? ", " + std::to_string(i % w) : "") + "]",
            v[i], ranges[ranges.size() == 1 ? 0 : i % w]);
    for (std::size_t i = 0; i < rows * w; ++i) set(i / w, i % w, v[i]);
  }
  /// The number of rows of a table of `cols` columns whose length is part of the state
  /// (`current` when writing; read back, within `n`).
  std::size_t rows(const std::string& name, std::size_t cols, std::size_t current,
                   const Count& n) const {
    if (!in_) return current;
    const Dims d = dims(name);
    if (d.size() != 2 || d[1] != cols)
      refuse(name, ": has shape " + shape(d) + ", not (n, " + std::to_string(cols) + ")");
    if (!n.contains(d[0])) refuse(name, ": " + std::to_string(d[0]) + " rows, not " + n.text());
    return d[0];
  }
  /// A random stream: its four xoshiro256++ words and its draw count.
  void stream(const std::string& name, Engine& e) {
    const auto& s = e.state();
    if (!in_)
      return out_->write(g_ + "/" + name,
                         std::vector<std::uint64_t>{s[0], s[1], s[2], s[3], e.draws()}, {5});
    const auto v = read<std::uint64_t>(name, {5});
    // The all-zero state is xoshiro256++'s fixed point: it would draw zeros forever, and samplers
    // that reject a zero would never return. make_stream never starts there; only an edit can.
    if ((v[0] | v[1] | v[2] | v[3]) == 0)
      refuse(name,
             ": a random stream in the all-zero state (a fixed point of xoshiro256++), "
             "which no run reaches: the file was edited");
    e = Engine({v[0], v[1], v[2], v[3]}, v[4]);
  }
  /// Checks, when reading, against values declared later (a particle's time against the time):
  /// get(i) of `rows` values, named as column `col` of `name`, within r.
  template <class Get>
  void each(const std::string& name, std::size_t rows, std::size_t col, Get get,
            const Real& r) const {
    for (std::size_t i = 0; in_ && i < rows; ++i)
      check(name + "[" + std::to_string(i) + ", " + std::to_string(col) + "]", get(i), r);
  }
  template <class Ok>
  void require(const std::string& name, Ok ok, const char* what) const {
    if (in_ && !ok()) refuse(name, std::string(": ") + what);
  }

  [[noreturn]] void refuse(const std::string& name, const std::string& what) const {
    throw std::runtime_error(in_->path() + ": malformed ensemble state " + g_ + ": dataset " + g_ +
                             "/" + name + what);
  }

 private:
  static std::string shape(const Dims& d) {
    std::string s = "(";
    for (std::size_t k = 0; k < d.size(); ++k) s += (k ? ", " : "") + std::to_string(d[k]);
    return s + (d.size() == 1 ? ",)" : ")");
  }
  Dims dims(const std::string& name) const {
    if (!in_->exists(g_ + "/" + name)) refuse(name, ": missing");
    return in_->dims(g_ + "/" + name);
  }
  template <class T>
  std::vector<T> read(const std::string& name, const Dims& want) const {
    const Dims d = dims(name);
    if (d != want) refuse(name, ": has shape " + shape(d) + ", not " + shape(want));
    if constexpr (std::is_same_v<T, double>)
      return in_->read_double(g_ + "/" + name);
    else
      return in_->read_uint64(g_ + "/" + name);
  }
  template <class T>
  void check(const std::string& what, T x, const Range<T>& r) const {
    if (!r.contains(x)) refuse(what, " = " + Range<T>::show(x) + ", not " + r.text());
  }
  H5Writer* out_ = nullptr;
  const H5Reader* in_ = nullptr;
  std::string g_;
};

/// Writes `engine`'s state (its visit_state) under `group`.
template <class E>
void save_state(const E& engine, H5Writer& out, const std::string& group) {
  StateArchive a(out, group);
  const_cast<E&>(engine).visit_state(a);  // writing only reads the members
}

/// An index stream as its buffer of (index, bits) rows, its position and its lanes, under
/// `name`; the indices lie in [0, range).
inline void visit_index_stream(StateArchive& a, const std::string& name, IndexStream& s,
                               std::uint32_t range) {
  std::array<IndexBits, IndexStream::kBuffer> buffer = s.buffer();
  std::uint64_t position = s.position();
  std::array<Engine, IndexStream::kLanes> lanes;
  for (unsigned l = 0; l < IndexStream::kLanes; ++l) lanes[l] = s.lane(l);
  a.table<std::uint64_t>(
      name + "/buffer", IndexStream::kBuffer, 2,
      {below(range, "the range"), up_to(0xFFFFFFFFu, "2^32 - 1")},
      [&](std::size_t i, std::size_t k) -> std::uint64_t {
        return k ? buffer[i].bits : buffer[i].i;
      },
      [&](std::size_t i, std::size_t k, std::uint64_t x) {
        (k ? buffer[i].bits : buffer[i].i) = static_cast<std::uint32_t>(x);
      });
  a.pack(name + "/position", word("position", position, up_to(IndexStream::kBlock, "the block")));
  for (unsigned l = 0; l < IndexStream::kLanes; ++l)
    a.stream(name + "/lane_" + std::to_string(l), lanes[l]);
  if (a.reading()) s = IndexStream(range, lanes, buffer, static_cast<unsigned>(position));
}

}  // namespace granboltz
