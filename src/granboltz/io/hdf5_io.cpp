#include "granboltz/io/hdf5_io.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace granboltz {

namespace {

// HDF5 prints its error stack by default; we report errors ourselves, once.
struct SilenceHdf5 {
  SilenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};
const SilenceHdf5 kSilence;

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

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

H5Writer::H5Writer(const std::string& path)
    : path_(path), tmp_(path + ".tmp." + std::to_string(::getpid())) {
  // Refused here, before any work, rather than when the finished file is renamed into place.
  if (path.empty()) fail("the output path is empty");
  std::error_code ec;
  if (path.back() == '/' || std::filesystem::is_directory(path, ec))
    fail(path + ": is a directory; give the output file's name");
  file_ = H5Fcreate(tmp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) fail(path + ": cannot create output file (is the directory writable?)");
}

H5Writer::~H5Writer() {
  if (file_ >= 0) {
    H5Fclose(file_);
    std::remove(tmp_.c_str());
  }
}

void H5Writer::group(const std::string& path) {
  if (H5Lexists(file_, path.c_str(), H5P_DEFAULT) > 0) return;
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle g{H5Gcreate2(file_, path.c_str(), lcpl.id, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  if (g.id < 0) fail(path_ + ": cannot create group " + path);
}

void H5Writer::write_raw(const std::string& path, hid_t mem_type, hid_t file_type,
                         const void* data, const Dims& dims) {
  Handle space{dims.empty() ? H5Screate(H5S_SCALAR)
                            : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
               H5Sclose};
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  // Large datasets are chunked and compressed; small ones stay contiguous.
  if (!dims.empty() && product(dims) >= 4096) {
    Dims chunk = dims;
    hsize_t total = product(chunk);
    for (std::size_t k = 0; k < chunk.size() && total > 65536; ++k) {
      total /= chunk[k];
      chunk[k] = std::max<hsize_t>(1, 65536 / std::max<hsize_t>(1, total));
      total *= chunk[k];
    }
    H5Pset_chunk(dcpl.id, static_cast<int>(chunk.size()), chunk.data());
    H5Pset_deflate(dcpl.id, 4);
  }
  Handle ds{H5Dcreate2(file_, path.c_str(), file_type, space.id, lcpl.id, dcpl.id, H5P_DEFAULT),
            H5Dclose};
  if (ds.id < 0) fail(path_ + ": cannot create dataset " + path);
  if (product(dims) > 0 && H5Dwrite(ds.id, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(path_ + ": cannot write dataset " + path);
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
  if (H5Fclose(file_) < 0) {
    file_ = -1;
    std::remove(tmp_.c_str());
    fail(path_ + ": cannot finish writing the output file");
  }
  file_ = -1;
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    std::remove(tmp_.c_str());
    fail(path_ + ": cannot move the finished output into place");
  }
}

H5Reader::H5Reader(const std::string& path) : path_(path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) fail(path + ": is a directory, not an HDF5 file");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    fail(path + ": not a readable HDF5 file");
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

Dims H5Reader::dims(const std::string& path) const {
  Handle ds{H5Dopen2(file_, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (ds.id < 0) fail(path_ + ": missing dataset " + path);
  Handle space{H5Dget_space(ds.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 0) fail(path_ + ": unreadable dataset " + path);
  Dims d(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id, d.data(), nullptr);
  return d;
}

void H5Reader::read_raw(const std::string& path, hid_t mem_type, void* out,
                        std::size_t count) const {
  Handle ds{H5Dopen2(file_, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (ds.id < 0) fail(path_ + ": missing dataset " + path);
  if (count > 0 && H5Dread(ds.id, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    fail(path_ + ": cannot read dataset " + path + " (corrupt or truncated file?)");
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
  Handle ds{H5Dopen2(file_, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (ds.id < 0) fail(path_ + ": missing dataset " + path);
  Handle type{H5Dget_type(ds.id), H5Tclose};
  std::vector<unsigned char> v(product(dims(path)) * H5Tget_size(type.id));
  if (!v.empty() && H5Dread(ds.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    fail(path_ + ": cannot read dataset " + path);
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

}  // namespace granboltz
