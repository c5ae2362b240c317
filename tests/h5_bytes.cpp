// h5_bytes FILE sample SEED N   prints N positions "CLASS OFFSET BIT" of each class of the file's bytes
// h5_bytes FILE flip OFFSET BIT  flips that bit of the file in place
// h5_bytes FILE locate DATASET    prints where the dataset's stored data begins (its first chunk)
// A test helper for the corruption fuzz (test_corruption_fuzz.sh).  The classes are HDF5's superblock,
// the stored data of each kind of dataset (the chunks of a chunked one, the block of a contiguous one;
// frames' datasets pooled by name, "data:/frames/*/alpha_s"), and "metadata": every other byte of the file
// (object headers with their attributes, chunk indexes, link heaps, free space).  Positions are drawn
// uniformly within each class from a seeded stream, so a failing position can be replayed.
#include "base/h5.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <string>
#include <vector>

namespace {

using Range = std::pair<haddr_t, haddr_t>; // [begin, end) in the file

// The byte ranges of each class but "metadata".
// The byte ranges of each class but "metadata"; with `only`, of that dataset alone, unpooled.
std::map<std::string, std::vector<Range>> storedRanges(const rcfd::h5::File &f, const std::string &only = "") {
  std::map<std::string, std::vector<Range>> ranges;
  H5F_info2_t info;
  if (H5Fget_info2(f.id(), &info) < 0) throw rcfd::h5::Error("cannot read the superblock of '" + f.path() + "'");
  ranges["superblock"].emplace_back(0, info.super.super_size);
  std::vector<std::string> names;
  H5Lvisit(
      f.id(), H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char *link, const H5L_info_t *, void *data) -> herr_t {
        static_cast<std::vector<std::string> *>(data)->push_back(std::string("/") + link);
        return 0;
      },
      &names);
  static const std::regex frame("/frames/[0-9]{6}/");
  for (const std::string &name : names) {
    rcfd::h5::Id o(H5Oopen(f.id(), name.c_str(), H5P_DEFAULT), H5Oclose);
    if (H5Iget_type(o) != H5I_DATASET || (!only.empty() && name != only)) continue;
    auto &out = ranges["data:" + (only.empty() ? std::regex_replace(name, frame, "/frames/*/") : name)];
    rcfd::h5::Id dcpl(H5Dget_create_plist(o), H5Pclose);
    if (H5Pget_layout(dcpl) == H5D_CHUNKED) {
      hsize_t chunks = 0;
      rcfd::h5::Id space(H5Dget_space(o), H5Sclose);
      if (H5Dget_num_chunks(o, space, &chunks) < 0) throw rcfd::h5::Error("cannot count the chunks of " + name);
      for (hsize_t i = 0; i < chunks; ++i) {
        hsize_t offset[2], size = 0;
        unsigned mask = 0;
        haddr_t address = HADDR_UNDEF;
        if (H5Dget_chunk_info(o, space, i, offset, &mask, &address, &size) < 0)
          throw rcfd::h5::Error("cannot locate chunk " + std::to_string(i) + " of " + name);
        if (address != HADDR_UNDEF && size > 0) out.emplace_back(address, address + size);
      }
    } else if (H5Pget_layout(dcpl) == H5D_CONTIGUOUS) {
      const haddr_t address = H5Dget_offset(o);
      const hsize_t size = H5Dget_storage_size(o);
      if (address != HADDR_UNDEF && size > 0) out.emplace_back(address, address + size);
    } // compact data sits in its object header: metadata
  }
  return ranges;
}

// The bytes of [0, fileSize) in none of `taken`.
std::vector<Range> complement(std::vector<Range> taken, haddr_t fileSize) {
  std::sort(taken.begin(), taken.end());
  std::vector<Range> rest;
  haddr_t at = 0;
  for (const auto &[b, e] : taken) {
    if (b > at) rest.emplace_back(at, b);
    at = std::max(at, e);
  }
  if (at < fileSize) rest.emplace_back(at, fileSize);
  return rest;
}

void sample(const std::string &path, unsigned long seed, int perClass) {
  auto ranges = storedRanges(rcfd::h5::File::openRead(path, MPI_COMM_NULL));
  std::vector<Range> all;
  for (const auto &[name, r] : ranges) all.insert(all.end(), r.begin(), r.end());
  ranges["metadata"] = complement(all, std::filesystem::file_size(path));
  std::mt19937_64 random(seed);
  for (const auto &[name, r] : ranges) {
    haddr_t bytes = 0;
    for (const auto &[b, e] : r) bytes += e - b;
    if (bytes == 0) continue;
    for (int i = 0; i < perClass; ++i) {
      haddr_t pick = std::uniform_int_distribution<haddr_t>(0, bytes - 1)(random);
      size_t k = 0;
      while (pick >= r[k].second - r[k].first) pick -= r[k].second - r[k].first, ++k;
      std::printf("%s %llu %d\n", name.c_str(), static_cast<unsigned long long>(r[k].first + pick),
                  static_cast<int>(std::uniform_int_distribution<int>(0, 7)(random)));
    }
  }
}

void locate(const std::string &path, const std::string &dataset) {
  const auto ranges = storedRanges(rcfd::h5::File::openRead(path, MPI_COMM_NULL), dataset);
  const auto found = ranges.find("data:" + dataset);
  if (found == ranges.end() || found->second.empty())
    throw rcfd::h5::Error("'" + path + "' stores no data of '" + dataset + "'");
  std::printf("%llu\n", static_cast<unsigned long long>(std::min_element(found->second.begin(), found->second.end())->first));
}

void flip(const std::string &path, long long offset, int bit) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  char byte = 0;
  if (!file.seekg(offset) || !file.get(byte)) throw rcfd::h5::Error("cannot read byte " + std::to_string(offset) + " of '" + path + "'");
  byte = static_cast<char>(byte ^ (1 << bit));
  if (!file.seekp(offset) || !file.put(byte)) throw rcfd::h5::Error("cannot write byte " + std::to_string(offset) + " of '" + path + "'");
}

} // namespace

int main(int argc, char **argv) {
  const std::string command = argc > 2 ? argv[2] : "";
  if (!(argc == 5 && (command == "sample" || command == "flip")) && !(argc == 4 && command == "locate")) {
    std::fprintf(stderr, "usage: h5_bytes FILE sample SEED N | FILE flip OFFSET BIT | FILE locate DATASET\n");
    return 2;
  }
  try {
    if (command == "sample") sample(argv[1], std::stoul(argv[3]), std::stoi(argv[4]));
    else if (command == "locate") locate(argv[1], argv[3]);
    else flip(argv[1], std::stoll(argv[3]), std::stoi(argv[4]));
  } catch (const std::exception &e) {
    std::fprintf(stderr, "h5_bytes: %s\n", e.what());
    return 1;
  }
  return 0;
}
