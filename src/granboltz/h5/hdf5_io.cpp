#include "granboltz/h5/hdf5_io.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace granboltz {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

// The temporary files this process has open, for a signal handler to remove: fixed slots of
// fixed size, claimed and released with atomics (no allocation, no lock in the handler).
constexpr int kSlots = 16;
constexpr std::size_t kSlotPath = 4096;
char g_slot_path[kSlots][kSlotPath];
std::atomic<bool> g_slot_live[kSlots];
std::atomic<bool> g_slot_taken[kSlots];

int claim_slot(const std::string& path) {
  if (path.size() >= kSlotPath) return -1;
  for (int k = 0; k < kSlots; ++k) {
    bool expected = false;
    if (!g_slot_taken[k].compare_exchange_strong(expected, true)) continue;
    std::memcpy(g_slot_path[k], path.c_str(), path.size() + 1);
    g_slot_live[k].store(true);
    return k;
  }
  return -1;  // more than kSlots writers at once: that file is not removed by a signal
}

void release_slot(int k) {
  if (k < 0) return;
  g_slot_live[k].store(false);
  g_slot_taken[k].store(false);
}

std::string file_kind(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a directory";
  return "not a regular file";
}

// The pid in a temporary name "<name>.tmp.<pid>" or "<name>.tmp.<pid>.<suffix>", 0 if the name
// does not parse (it is then not one of ours and is left alone).
long temporary_pid(const std::string& rest) {
  const std::string digits = rest.substr(0, rest.find('.'));
  long pid = 0;
  const auto res = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
  if (digits.empty() || res.ec != std::errc() || res.ptr != digits.data() + digits.size()) return 0;
  return pid;
}

// 64-bit FNV-1a, to combine the per-dataset hashes with their names, types and shapes.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void value(T x) {
    add(&x, sizeof x);
  }
};

// True if the current HDF5 error stack reports a checksum mismatch (Fletcher32 on chunks, or the
// metadata checksums of object headers), so that the message can say so.
bool checksum_failed() {
  bool found = false;
  auto visit = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    const std::string desc = e->desc ? e->desc : "";
    if (desc.find("checksum") != std::string::npos || desc.find("Fletcher32") != std::string::npos)
      *static_cast<bool*>(data) = true;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, visit, &found);
  return found;
}

// HDF5's metadata checksum (Jenkins lookup3), exported by the library though not in its headers.
extern "C" uint32_t H5_checksum_metadata(const void* data, size_t len, uint32_t initval);

// H5Fget_file_image (HDF5 1.10.8) clears the "open for writing" flag in the image's superblock
// (version 2 or 3) without updating the superblock's checksum, so that the file would not open
// ("incorrect metadata checksum"). Recomputes that checksum.
void fix_superblock_checksum(std::vector<unsigned char>& image) {
  if (image.size() < 12 || image[8] < 2) return;  // superblocks 0 and 1 have no checksum
  const std::size_t end = 12 + 4 * static_cast<std::size_t>(image[9]);  // 4 addresses
  if (image.size() < end + 4) return;
  const std::uint32_t sum = H5_checksum_metadata(image.data(), end, 0);
  for (int k = 0; k < 4; ++k) image[end + k] = static_cast<unsigned char>(sum >> (8 * k));
}

// The hash of one dataset: its path, type (class, size, sign), shape and stored bytes.
std::uint64_t dataset_hash(const std::string& path, int type_class, std::size_t type_size, int sign,
                           const Dims& dims, const void* bytes, std::size_t n) {
  Fnv f;
  f.add(path.data(), path.size());
  f.value(type_class);
  f.value(type_size);
  f.value(sign);
  f.value(dims.size());
  for (auto d : dims) f.value(static_cast<std::uint64_t>(d));
  f.value(static_cast<std::uint64_t>(n));
  f.value(n ? H5_checksum_metadata(bytes, n, 0) : 0u);
  f.value(n ? H5_checksum_metadata(bytes, n, 0x9e3779b9u) : 0u);
  return f.h;
}

std::uint64_t combine(std::vector<std::pair<std::string, std::uint64_t>> hashes) {
  std::sort(hashes.begin(), hashes.end());
  Fnv f;
  for (const auto& [path, h] : hashes) f.value(h);
  return f.h;
}

// A stored or memory type as NumPy names it ("float64", "uint64", "int32"), for messages and
// for comparing a dataset's type with the one a reader asks for (byte order aside).
std::string type_name(hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::string bits = std::to_string(8 * H5Tget_size(type));
  if (cls == H5T_FLOAT) return "float" + bits;
  if (cls == H5T_INTEGER) return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + bits;
  if (cls == H5T_STRING) return "string";
  return "an HDF5 type of class " + std::to_string(static_cast<int>(cls));
}

hsize_t product(const Dims& dims) {
  hsize_t n = 1;
  for (auto d : dims) n *= d;
  return n;
}

struct Handle {  // closes an HDF5 id with the right function
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

}  // namespace

void silence_hdf5_errors() {
  thread_local bool done = false;
  if (!done) H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  done = true;
}

void remove_temporaries_now() noexcept {
  for (int k = 0; k < kSlots; ++k)
    if (g_slot_live[k].load()) ::unlink(g_slot_path[k]);
}

void check_output_path(const std::string& path, const std::vector<std::string>& inputs) {
  if (path.empty()) fail("the output path is empty");
  if (path.back() == '/') fail(path + ": is a directory; give the output file's name");
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  struct stat d {};
  if (::stat(dir.c_str(), &d) != 0 || !S_ISDIR(d.st_mode))
    fail(path + ": directory " + dir.string() + " does not exist; create it first");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return;  // a new file
  if (S_ISDIR(st.st_mode)) fail(path + ": is a directory; give the output file's name");
  if (!S_ISREG(st.st_mode))
    fail(path + ": exists and is " + file_kind(st.st_mode) +
         "; an output is written only as a new or a regular file");
  for (const auto& in : inputs) {
    struct stat is {};
    if (!in.empty() && ::stat(in.c_str(), &is) == 0 && is.st_dev == st.st_dev &&
        is.st_ino == st.st_ino)
      fail(path + ": is the input " + in + " (the same file); the output must be another file");
  }
}

void check_input_file(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    fail(path + (errno == ENOENT ? std::string(": no such file")
                                 : ": cannot open " + what + " (" + std::strerror(errno) + ")"));
  if (S_ISDIR(st.st_mode)) fail(path + ": is a directory, not " + what);
  if (!S_ISREG(st.st_mode)) fail(path + ": is " + file_kind(st.st_mode) + ", not " + what);
}

H5Writer::H5Writer(const std::string& path) : path_(path) {
  silence_hdf5_errors();
  // Refused here, before any work, rather than when the finished file is renamed into place.
  check_output_path(path);
  // A fresh name that no one can have planted: mkostemp creates it with O_EXCL, which neither
  // follows nor reuses an existing name (a symbolic link there is not written through).
  std::string name = path + ".tmp." + std::to_string(::getpid()) + ".XXXXXX";
  fd_ = ::mkostemp(name.data(), O_CLOEXEC);
  if (fd_ < 0)
    fail(path + ": cannot create output file (" + std::strerror(errno) +
         "; is the directory writable?)");
  tmp_ = name;
  ::fchmod(fd_, 0644);
  slot_ = claim_slot(tmp_);
  // Held until the finished file is in place: a second run on the same output sees it below.
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    discard();
    fail(path + ": cannot lock the temporary output file (" + std::strerror(errno) + ")");
  }
  {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    const std::string prefix = p.filename().string() + ".tmp.";
    const std::string own = fs::path(tmp_).filename().string();
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string other = entry.path().filename().string();
      if (other.rfind(prefix, 0) != 0 || other == own) continue;
      const long pid = temporary_pid(other.substr(prefix.size()));
      if (pid <= 0) continue;
      struct stat st {};
      if (::lstat(entry.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
      const int fd = ::open(entry.path().c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
      if (fd < 0) continue;
      const bool held = ::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
      if (!held) ::unlink(entry.path().c_str());  // its writer is gone
      ::close(fd);
      if (held) {
        discard();
        fail(path + ": another process (pid " + std::to_string(pid) +
             ") is writing this output now; wait for it or choose another output");
      }
    }
  }
  // The file is built in memory (HDF5's core driver, no backing store) and written out by
  // commit() alone. HDF5 then never meets a failing write: after one, HDF5 1.10 cannot close the
  // file, and its exit handler crashes on the half-closed file (SIGSEGV on a full disk).
  Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  H5Pset_fapl_core(fapl.id, 1 << 20, 0);
  // Version-2 object headers carry a checksum: it covers the attributes and the compact
  // (scalar) datasets, which Fletcher32 cannot (it needs chunks). HDF5 1.10 format.
  H5Pset_libver_bounds(fapl.id, H5F_LIBVER_V110, H5F_LIBVER_V110);
  file_ = H5Fcreate(tmp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id);
  if (file_ < 0) {
    discard();
    fail(path + ": cannot create the HDF5 file in memory");
  }
}

H5Writer::~H5Writer() { discard(); }

void H5Writer::discard() {
  if (file_ >= 0) H5Fclose(file_);  // in memory: nothing to flush, cannot fail on the disk
  file_ = -1;
  if (fd_ >= 0) {
    ::unlink(tmp_.c_str());  // while still locked, so that no one takes it for a stale file
    ::close(fd_);
  }
  fd_ = -1;
  release_slot(slot_);
  slot_ = -1;
}

std::uint64_t H5Writer::digest() const { return combine(digests_); }

void H5Writer::group(const std::string& path) {
  if (H5Lexists(file_, path.c_str(), H5P_DEFAULT) > 0) return;
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle g{H5Gcreate2(file_, path.c_str(), lcpl.id, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  if (g.id < 0) fail(path_ + ": cannot create group " + path);
}

void H5Writer::write_raw(const std::string& path, hid_t mem_type, hid_t file_type, const void* data,
                         const Dims& dims) {
  Handle space{dims.empty() ? H5Screate(H5S_SCALAR)
                            : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
               H5Sclose};
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  if (dims.empty()) {
    // A scalar cannot be chunked, so Fletcher32 cannot cover it: stored compact, inside its
    // object header, whose own checksum covers it (version-2 headers, see the constructor).
    H5Pset_layout(dcpl.id, H5D_COMPACT);
  } else if (product(dims) > 0) {
    // Every other dataset is chunked (at most 64 Ki elements a chunk) and checksummed with
    // Fletcher32; large ones are also compressed. Empty datasets hold no data to check.
    Dims chunk = dims;
    hsize_t total = product(chunk);
    for (std::size_t k = 0; k < chunk.size() && total > 65536; ++k) {
      total /= chunk[k];
      chunk[k] = std::max<hsize_t>(1, 65536 / std::max<hsize_t>(1, total));
      total *= chunk[k];
    }
    H5Pset_chunk(dcpl.id, static_cast<int>(chunk.size()), chunk.data());
    // Text (the manifest: fixed-length, mostly padding) is compressed whatever its size.
    if (product(dims) >= 4096 || H5Tget_class(file_type) == H5T_STRING) H5Pset_deflate(dcpl.id, 4);
    H5Pset_fletcher32(dcpl.id);  // after deflate: the checksum is of the stored bytes
  }
  Handle ds{H5Dcreate2(file_, path.c_str(), file_type, space.id, lcpl.id, dcpl.id, H5P_DEFAULT),
            H5Dclose};
  if (ds.id < 0) fail(path_ + ": cannot create dataset " + path);
  if (product(dims) > 0 && H5Dwrite(ds.id, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(path_ + ": cannot write dataset " + path);
  const int sign =
      H5Tget_class(file_type) == H5T_INTEGER ? static_cast<int>(H5Tget_sign(file_type)) : -1;
  digests_.emplace_back(
      path, dataset_hash(path, static_cast<int>(H5Tget_class(file_type)), H5Tget_size(file_type),
                         sign, dims, data, product(dims) * H5Tget_size(file_type)));
}

void H5Writer::write(const std::string& path, const std::vector<double>& data, const Dims& dims) {
  if (data.size() != product(dims)) fail("internal: size mismatch for " + path);
  write_raw(path, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, data.data(), dims);
}
void H5Writer::write(const std::string& path, const std::vector<std::uint64_t>& data,
                     const Dims& dims) {
  if (data.size() != product(dims)) fail("internal: size mismatch for " + path);
  write_raw(path, H5T_NATIVE_UINT64, H5T_STD_U64LE, data.data(), dims);
}
void H5Writer::write(const std::string& path, const std::vector<std::int64_t>& data,
                     const Dims& dims) {
  if (data.size() != product(dims)) fail("internal: size mismatch for " + path);
  write_raw(path, H5T_NATIVE_INT64, H5T_STD_I64LE, data.data(), dims);
}

void H5Writer::write(const std::string& path, const std::vector<std::string>& data) {
  std::size_t width = 1;
  for (const std::string& s : data) width = std::max(width, s.size());
  std::vector<char> bytes(width * data.size(), '\0');
  for (std::size_t k = 0; k < data.size(); ++k)
    std::copy(data[k].begin(), data[k].end(), &bytes[k * width]);
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, width);
  H5Tset_strpad(type.id, H5T_STR_NULLPAD);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  write_raw(path, type.id, type.id, bytes.data(), {data.size()});
}

void H5Writer::attr(const std::string& object, const std::string& name, const std::string& value) {
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, value.empty() ? 1 : value.size());
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate_by_name(file_, object.c_str(), name.c_str(), type.id, space.id, H5P_DEFAULT,
                             H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  const char* data = value.empty() ? "" : value.c_str();
  if (a.id < 0 || H5Awrite(a.id, type.id, data) < 0)
    fail(path_ + ": cannot write attribute " + name + " of " + object);
}

void H5Writer::attr(const std::string& object, const std::string& name, double value) {
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate_by_name(file_, object.c_str(), name.c_str(), H5T_IEEE_F64LE, space.id,
                             H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0 || H5Awrite(a.id, H5T_NATIVE_DOUBLE, &value) < 0)
    fail(path_ + ": cannot write attribute " + name + " of " + object);
}

void H5Writer::attr(const std::string& object, const std::string& name, std::uint64_t value) {
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate_by_name(file_, object.c_str(), name.c_str(), H5T_STD_U64LE, space.id,
                             H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0 || H5Awrite(a.id, H5T_NATIVE_UINT64, &value) < 0)
    fail(path_ + ": cannot write attribute " + name + " of " + object);
}

void H5Writer::commit() {
  // The image of the finished file, then the bytes to disk with every error checked (ENOSPC,
  // EFBIG under ulimit -f with SIGXFSZ ignored, EIO), then fsync and the atomic rename.
  // Flushed first: H5Fget_file_image alone leaves the superblock's end-of-file address stale.
  const ssize_t size =
      H5Fflush(file_, H5F_SCOPE_LOCAL) < 0 ? -1 : H5Fget_file_image(file_, nullptr, 0);
  std::vector<unsigned char> image(size > 0 ? static_cast<std::size_t>(size) : 0);
  if (size <= 0 || H5Fget_file_image(file_, image.data(), image.size()) != size) {
    discard();
    fail(path_ + ": cannot finish the HDF5 file");
  }
  H5Fclose(file_);
  file_ = -1;
  fix_superblock_checksum(image);
  std::size_t done = 0;
  while (done < image.size()) {
    const ssize_t n = ::write(fd_, image.data() + done, image.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = n < 0 ? std::strerror(errno) : "short write";
      discard();
      fail(path_ + ": cannot write the file (" + why + "); nothing was written to " + path_);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd_) != 0) {
    const std::string why = std::strerror(errno);
    discard();
    fail(path_ + ": cannot write the file (" + why + "); nothing was written to " + path_);
  }
  // Checked again: the output may have been replaced by a FIFO or a link since the start.
  struct stat st {};
  if (::lstat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    discard();
    fail(path_ + ": is now " + file_kind(st.st_mode) + "; nothing was written to it");
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    discard();
    fail(path_ + ": cannot move the finished file into place (" + why + ")");
  }
  release_slot(slot_);  // the name is the output's now: a signal must not remove it
  slot_ = -1;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(path_ + ": cannot close the file (" + std::strerror(errno) + ")");
}

H5Reader::H5Reader(const std::string& path) : path_(path) {
  silence_hdf5_errors();
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) fail(path + ": no such file");
  if (S_ISDIR(st.st_mode)) fail(path + ": is a directory, not an HDF5 file");
  // A FIFO would block HDF5's open, a device would be read without end.
  if (!S_ISREG(st.st_mode)) fail(path + ": is " + file_kind(st.st_mode) + ", not an HDF5 file");
  if (H5Fis_hdf5(path.c_str()) <= 0) fail(path + ": not a readable HDF5 file");
  file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) fail(path + ": cannot open HDF5 file (corrupt or truncated?)");
}

H5Reader::~H5Reader() {
  if (file_ >= 0) H5Fclose(file_);
}

bool H5Reader::exists(const std::string& path) const {
  // Check every component: H5Lexists fails on a path whose parent is missing.
  std::size_t pos = 0;
  while ((pos = path.find('/', pos + 1)) != std::string::npos)
    if (H5Lexists(file_, path.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file_, path.c_str(), H5P_DEFAULT) > 0;
}

hid_t H5Reader::open_dataset(const std::string& path) const {
  const hid_t ds = H5Dopen2(file_, path.c_str(), H5P_DEFAULT);
  if (ds < 0) {
    if (checksum_failed())
      fail(path_ + ": checksum mismatch in dataset " + path + " (corrupt file)");
    fail(path_ + ": missing dataset " + path);
  }
  return ds;
}

void H5Reader::read_checked(hid_t ds, const std::string& path, hid_t mem_type, void* out) const {
  if (H5Dread(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0) return;
  if (checksum_failed()) fail(path_ + ": checksum mismatch in dataset " + path + " (corrupt file)");
  fail(path_ + ": cannot read dataset " + path + " (corrupt or truncated file?)");
}

Dims H5Reader::dims(const std::string& path) const {
  Handle ds{open_dataset(path), H5Dclose};
  Handle space{H5Dget_space(ds.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 0) fail(path_ + ": unreadable dataset " + path);
  Dims d(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id, d.data(), nullptr);
  return d;
}

void H5Reader::read_raw(const std::string& path, hid_t mem_type, void* out,
                        std::size_t count) const {
  Handle ds{open_dataset(path), H5Dclose};
  // Stored as it is asked for, or refused: HDF5 would convert an edited dataset (integers cast
  // to int32, velocities to float32) silently, and the reader would take rounded values.
  Handle type{H5Dget_type(ds.id), H5Tclose};
  if (type_name(type.id) != type_name(mem_type))
    fail(path_ + ": dataset " + path + ": has dtype " + type_name(type.id) + ", not " +
         type_name(mem_type));
  if (count > 0) read_checked(ds.id, path, mem_type, out);
}

std::vector<double> H5Reader::read_double(const std::string& path) const {
  std::vector<double> v(product(dims(path)));
  read_raw(path, H5T_NATIVE_DOUBLE, v.data(), v.size());
  return v;
}
std::vector<std::uint64_t> H5Reader::read_uint64(const std::string& path) const {
  std::vector<std::uint64_t> v(product(dims(path)));
  read_raw(path, H5T_NATIVE_UINT64, v.data(), v.size());
  return v;
}
std::vector<std::int64_t> H5Reader::read_int64(const std::string& path) const {
  std::vector<std::int64_t> v(product(dims(path)));
  read_raw(path, H5T_NATIVE_INT64, v.data(), v.size());
  return v;
}

std::vector<unsigned char> H5Reader::read_bytes(const std::string& path) const {
  Handle ds{open_dataset(path), H5Dclose};
  Handle type{H5Dget_type(ds.id), H5Tclose};
  std::vector<unsigned char> v(product(dims(path)) * H5Tget_size(type.id));
  if (!v.empty()) read_checked(ds.id, path, type.id, v.data());
  return v;
}

std::string H5Reader::attr_string(const std::string& object, const std::string& name) const {
  Handle a{H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0) fail(path_ + ": missing attribute " + name + " of " + object);
  Handle type{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(type.id) != H5T_STRING) fail(path_ + ": attribute " + name + " is not text");
  if (H5Tis_variable_str(type.id) > 0) {
    char* s = nullptr;
    Handle mem{H5Tcopy(H5T_C_S1), H5Tclose};
    H5Tset_size(mem.id, H5T_VARIABLE);
    H5Tset_cset(mem.id, H5Tget_cset(type.id));  // HDF5 converts no ASCII <-> UTF-8 (h5py's str)
    if (H5Aread(a.id, mem.id, &s) < 0) fail(path_ + ": cannot read attribute " + name);
    std::string out = s ? s : "";
    H5free_memory(s);
    return out;
  }
  std::string out(H5Tget_size(type.id), '\0');
  if (H5Aread(a.id, type.id, out.data()) < 0) fail(path_ + ": cannot read attribute " + name);
  while (!out.empty() && out.back() == '\0') out.pop_back();
  return out;
}

std::uint64_t H5Reader::attr_uint64(const std::string& object, const std::string& name) const {
  Handle a{H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  if (a.id < 0) fail(path_ + ": missing attribute " + name + " of " + object);
  std::uint64_t v = 0;
  if (H5Aread(a.id, H5T_NATIVE_UINT64, &v) < 0) fail(path_ + ": cannot read attribute " + name);
  return v;
}

bool H5Reader::has_attr(const std::string& object, const std::string& name) const {
  return (object == "/" || exists(object)) &&
         H5Aexists_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::vector<std::string> H5Reader::datasets() const {
  std::vector<std::string> names;
  auto visit = [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    if (info->type == H5O_TYPE_DATASET)
      static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
    return 0;
  };
  if (H5Ovisit(file_, H5_INDEX_NAME, H5_ITER_INC, visit, &names) < 0)
    fail(path_ + ": cannot list datasets (corrupt file?)");
  return names;
}

std::vector<std::string> H5Reader::damaged() const {
  std::vector<std::string> out;
  std::vector<std::string> names;
  try {
    names = datasets();
  } catch (const std::runtime_error&) {
    return {"/: the file's index of objects is unreadable"};
  }
  for (const auto& name : names) {
    try {
      read_bytes(name);
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      const std::string prefix = path_ + ": ";
      out.push_back(what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
    }
  }
  // Every attribute of every object too: a group holds no dataset whose checksum would reveal
  // a damaged header (the root's config, /provenance), yet the readers need its attributes.
  std::vector<std::string> objects;
  auto visit = [](hid_t, const char* name, const H5O_info_t*, void* data) -> herr_t {
    const std::string n = name;
    static_cast<std::vector<std::string>*>(data)->push_back(n == "." ? "/" : "/" + n);
    return 0;
  };
  if (H5Ovisit(file_, H5_INDEX_NAME, H5_ITER_INC, visit, &objects) < 0)
    return {"/: the file's index of objects is unreadable"};
  auto read_attribute = [](hid_t loc, const char* name, const H5A_info_t*, void*) -> herr_t {
    const Handle a{H5Aopen(loc, name, H5P_DEFAULT), H5Aclose};
    if (a.id < 0) return -1;
    const Handle type{H5Aget_type(a.id), H5Tclose};
    const Handle space{H5Aget_space(a.id), H5Sclose};
    if (type.id < 0 || space.id < 0) return -1;
    const hssize_t n = H5Sget_simple_extent_npoints(space.id);
    if (n < 0) return -1;
    if (H5Tis_variable_str(type.id) > 0) {
      std::vector<char*> strings(static_cast<std::size_t>(n), nullptr);
      const Handle mem{H5Tcopy(H5T_C_S1), H5Tclose};
      H5Tset_size(mem.id, H5T_VARIABLE);
      H5Tset_cset(mem.id, H5Tget_cset(type.id));  // no ASCII <-> UTF-8 conversion in HDF5
      const herr_t status = H5Aread(a.id, mem.id, strings.data());
      for (char* s : strings) H5free_memory(s);
      return status < 0 ? -1 : 0;
    }
    if (H5Tdetect_class(type.id, H5T_VLEN) > 0) return 0;  // granboltz writes none
    std::vector<unsigned char> bytes(H5Tget_size(type.id) * static_cast<std::size_t>(n));
    return H5Aread(a.id, type.id, bytes.data()) < 0 ? -1 : 0;
  };
  for (const auto& object : objects)
    if (H5Aiterate_by_name(file_, object.c_str(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
                           read_attribute, nullptr, H5P_DEFAULT) < 0)
      out.push_back(object + ": its attributes are unreadable (damaged object header?)");
  return out;
}

std::uint64_t H5Reader::digest() const {
  std::vector<std::pair<std::string, std::uint64_t>> hashes;
  for (const auto& name : datasets()) {
    Handle ds{open_dataset(name), H5Dclose};
    Handle type{H5Dget_type(ds.id), H5Tclose};
    const H5T_class_t cls = H5Tget_class(type.id);
    const int sign = cls == H5T_INTEGER ? static_cast<int>(H5Tget_sign(type.id)) : -1;
    const std::vector<unsigned char> bytes = read_bytes(name);
    hashes.emplace_back(name, dataset_hash(name, static_cast<int>(cls), H5Tget_size(type.id), sign,
                                           dims(name), bytes.data(), bytes.size()));
  }
  return combine(hashes);
}

}  // namespace granboltz
