#include "database/stored_frame.hpp"

#include <climits>
#include <cmath>
#include <cstdio>

namespace rcfd {

namespace {

constexpr const char *kVersion3Datasets =
    "a version 3 frame holds alpha_s, moving_row, moving_row_ptr, shift_col and shift_val (shift_quantum when "
    "/metadata has weight_bits)";

const char *weightDataset(int weightBits) { return weightBits > 0 ? "shift_quantum" : "shift_val"; }

void requireDataset(const h5::File &f, const std::string &group, const std::string &where, const std::string &name) {
  if (!f.exists(group + "/" + name))
    throw h5::Error(where + ": dataset " + name + " is missing; " + kVersion3Datasets);
}

hsize_t length(const h5::File &f, const std::string &dataset) {
  const auto dims = f.extents(dataset);
  return dims.size() == 1 ? dims[0] : 0;
}

int storedWeightBits(const h5::File &f) {
  return f.hasAttribute("/metadata", "weight_bits") ? static_cast<int>(f.readAttrInt("/metadata", "weight_bits"))
                                                    : 0;
}

} // namespace

std::string frameGroup(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "/frames/%06d", k);
  return name;
}

void throwDamagedFrame(const h5::Damaged &damaged, const h5::File &f, int k) {
  const std::string group = frameGroup(k) + "/";
  const std::string what = damaged.object.rfind(group, 0) == 0 ? "dataset " + damaged.object.substr(group.size())
                                                                : "'" + damaged.object + "'";
  throw h5::Damaged("database '" + f.path() + "', frame " + std::to_string(k) + ": " + what + " is damaged (" +
                        h5::Damaged::reason + ")",
                    damaged.object);
}

void writeStoredFrame(const h5::File &f, const std::string &group, const FrameRecord &frame, long long version,
                      int weightBits) {
  const CsrMatrix &T = frame.shift;
  f.createGroup(group);
  f.write(group + "/alpha_s", frame.alphaS);
  if (version < 3) {
    f.write(group + "/shift_row_ptr", T.rowPtr);
    f.write(group + "/shift_col", T.col);
    f.write(group + "/shift_val", T.val);
    return;
  }
  std::vector<int32_t> moving, col;
  std::vector<int64_t> ptr{0};
  std::vector<double> val;
  for (int j = 0; j < T.n; ++j) {
    const int64_t first = T.rowPtr[j], count = T.rowPtr[j + 1] - first;
    if (isIdentityRow(j, T.col.data() + first, T.val.data() + first, static_cast<std::size_t>(count))) continue;
    moving.push_back(j);
    col.insert(col.end(), T.col.begin() + first, T.col.begin() + first + count);
    val.insert(val.end(), T.val.begin() + first, T.val.begin() + first + count);
    ptr.push_back(static_cast<int64_t>(col.size()));
  }
  f.write(group + "/moving_row", moving);
  if (col.size() <= static_cast<size_t>(INT32_MAX)) // half the bytes; the reader converts
    f.write(group + "/moving_row_ptr", std::vector<int32_t>(ptr.begin(), ptr.end()));
  else
    f.write(group + "/moving_row_ptr", ptr);
  f.write(group + "/shift_col", col);
  if (weightBits == 0) {
    f.write(group + "/shift_val", val);
    return;
  }
  const double scale = std::ldexp(1.0, weightBits);
  std::vector<uint16_t> quantum(val.size());
  for (size_t e = 0; e < val.size(); ++e) quantum[e] = static_cast<uint16_t>(val[e] * scale - 1.0); // exact
  f.write(group + "/shift_quantum", quantum);
}

MovingRowIndex readMovingRowIndex(const h5::File &f, const std::string &group, const std::string &where, int cells,
                                  int weightBits) {
  for (const char *name : {"moving_row", "moving_row_ptr", "shift_col", weightDataset(weightBits)})
    requireDataset(f, group, where, name);
  MovingRowIndex index;
  index.movingRow = f.read<int32_t>(group + "/moving_row");
  const auto &rows = index.movingRow;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i] < 0 || rows[i] >= cells)
      throw h5::Error(where + ": moving_row " + std::to_string(i) + " names row " + std::to_string(rows[i]) +
                      ", outside the mesh's " + std::to_string(cells) + " cells");
    if (i > 0 && rows[i] <= rows[i - 1])
      throw h5::Error(where + ": moving_row is not ascending at position " + std::to_string(i) + " (row " +
                      std::to_string(rows[i]) + " after row " + std::to_string(rows[i - 1]) +
                      "); expected the moving rows' natural indices in strictly ascending order");
  }
  const hsize_t ptrLength = length(f, group + "/moving_row_ptr");
  if (ptrLength != rows.size() + 1)
    throw h5::Error(where + ": moving_row_ptr has " + std::to_string(ptrLength) + " entries, expected " +
                    std::to_string(rows.size() + 1) + " (one more than moving_row)");
  index.entries = length(f, group + "/shift_col");
  const hsize_t weights = length(f, group + "/" + weightDataset(weightBits));
  if (weights != index.entries)
    throw h5::Error(where + ": shift_col has " + std::to_string(index.entries) + " entries but " +
                    weightDataset(weightBits) + " has " + std::to_string(weights) + ", expected as many");
  return index;
}

std::vector<int64_t> readMovingRowPtr(const h5::File &f, const std::string &group, const std::string &where,
                                      const MovingRowIndex &index,
                                      const std::vector<std::pair<hsize_t, hsize_t>> &rowRuns,
                                      std::vector<std::pair<hsize_t, hsize_t>> *entryRuns) {
  std::vector<std::pair<hsize_t, hsize_t>> ptrRuns;
  for (auto [lo, hi] : rowRuns) ptrRuns.emplace_back(lo, hi + 1);
  auto ptr = f.readRuns<int64_t>(group + "/moving_row_ptr", ptrRuns);
  entryRuns->clear();
  int64_t previous = 0; // the entry runs must come in order, as the rows do
  size_t p = 0;
  for (auto [lo, hi] : rowRuns) {
    for (hsize_t i = lo; i <= hi; ++i, ++p)
      if (ptr[p] < previous || ptr[p] > static_cast<int64_t>(index.entries))
        throw h5::Error(where + ": moving_row_ptr is " + std::to_string(ptr[p]) + " at moving row " +
                        std::to_string(i) + (i < index.movingRow.size()
                                                 ? " (row " + std::to_string(index.movingRow[i]) + ")"
                                                 : std::string(" (the end)")) +
                        ", expected non-decreasing offsets from " + std::to_string(previous) + " up to the " +
                        std::to_string(index.entries) + " entries of shift_col");
      else
        previous = ptr[p];
    const int64_t first = ptr[p - (hi - lo + 1)], last = ptr[p - 1];
    if (last > first) entryRuns->emplace_back(first, last);
  }
  return ptr;
}

std::vector<double> readStoredWeights(const h5::File &f, const std::string &group,
                                      const std::vector<std::pair<hsize_t, hsize_t>> &runs, int weightBits) {
  if (weightBits == 0) return f.readRuns<double>(group + "/shift_val", runs);
  const auto quantum = f.readRuns<uint16_t>(group + "/shift_quantum", runs);
  const double unit = std::ldexp(1.0, -weightBits);
  std::vector<double> val(quantum.size());
  for (size_t e = 0; e < quantum.size(); ++e) val[e] = (quantum[e] + 1.0) * unit; // exact
  return val;
}

FrameRecord readStoredFrame(const h5::File &f, int k, int cells) try {
  const std::string g = frameGroup(k);
  FrameRecord r;
  r.alphaS = f.read<double>(g + "/alpha_s");
  r.shift.n = cells;
  if (f.readAttrInt("/", "format_version") < 3) {
    r.shift.rowPtr = f.read<int64_t>(g + "/shift_row_ptr");
    r.shift.col = f.read<int32_t>(g + "/shift_col");
    r.shift.val = f.read<double>(g + "/shift_val");
    return r;
  }
  const std::string where = "database '" + f.path() + "', frame " + std::to_string(k);
  const int bits = storedWeightBits(f);
  const MovingRowIndex index = readMovingRowIndex(f, g, where, cells, bits);
  const hsize_t rows = index.movingRow.size();
  std::vector<std::pair<hsize_t, hsize_t>> entryRuns;
  const auto ptr = readMovingRowPtr(f, g, where, index, rows > 0 ? decltype(entryRuns){{0, rows}} : decltype(entryRuns){},
                                    &entryRuns);
  const auto col = f.readRuns<int32_t>(g + "/shift_col", entryRuns);
  const auto val = readStoredWeights(f, g, entryRuns, bits);
  const int64_t base = rows > 0 ? ptr[0] : 0; // the entries read start at ptr[0]
  CsrMatrix &T = r.shift;
  T.rowPtr.assign(1, 0);
  size_t m = 0;
  for (int j = 0; j < cells; ++j) {
    if (m < rows && index.movingRow[m] == j) {
      for (int64_t e = ptr[m] - base; e < ptr[m + 1] - base; ++e)
        if (col[e] < 0 || col[e] >= cells)
          throw h5::Error(where + ": shift entry in row " + std::to_string(j) + " names cell " +
                          std::to_string(col[e]) + ", outside the mesh's " + std::to_string(cells) + " cells");
      T.col.insert(T.col.end(), col.begin() + (ptr[m] - base), col.begin() + (ptr[m + 1] - base));
      T.val.insert(T.val.end(), val.begin() + (ptr[m] - base), val.begin() + (ptr[m + 1] - base));
      ++m;
    } else { // an identity row
      T.col.push_back(j);
      T.val.push_back(1.0);
    }
    T.rowPtr.push_back(static_cast<int64_t>(T.col.size()));
  }
  return r;
} catch (const h5::Damaged &d) {
  throwDamagedFrame(d, f, k);
}

} // namespace rcfd
