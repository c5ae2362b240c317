// Eulerian frame files written (rcfd export-eulerian): a frame in the format
// the reader takes, and the solid velocity a shift implies.
#include "builders/eulerian/eulerian_frames.hpp"

#include "base/atomic_file.hpp"

#include <charconv>
#include <stdexcept>

namespace rcfd {

void writeEulerianFrame(const std::string &path, const Mesh &mesh, const EulerianFrame &frame) {
  const int N = mesh.numCells();
  if (static_cast<int>(frame.alphaS.size()) != N ||
      static_cast<int>(frame.gasVelocity.size()) != N ||
      static_cast<int>(frame.solidVelocity.size()) != N)
    throw std::invalid_argument("writeEulerianFrame: the frame does not match the mesh's cells");
  std::string out;
  out.reserve(static_cast<std::size_t>(N) * 120);
  char text[32];
  auto put = [&](double v, char sep) {
    const auto res = std::to_chars(text, text + sizeof text, v);
    out.append(text, res.ptr);
    out.push_back(sep);
  };
  for (int c = 0; c < N; ++c) {
    for (double x : mesh.cellCentre[c]) put(x, ' ');
    put(1.0 - frame.alphaS[c], ' ');
    for (double u : frame.gasVelocity[c]) put(u, ' ');
    put(frame.solidVelocity[c][0], ' ');
    put(frame.solidVelocity[c][1], ' ');
    put(frame.solidVelocity[c][2], '\n');
  }
  writeTextAtomically(path, out);
}

std::vector<Vec3> impliedSolidVelocity(const Mesh &mesh, const CsrMatrix &T, double dtRec) {
  std::vector<Vec3> u(T.n, Vec3{0.0, 0.0, 0.0});
  for (int j = 0; j < T.n; ++j)
    for (int64_t e = T.rowPtr[j]; e < T.rowPtr[j + 1]; ++e) {
      const int i = T.col[e];
      for (int a = 0; a < 3; ++a)
        u[i][a] += T.val[e] * (mesh.cellCentre[j][a] - mesh.cellCentre[i][a]) / dtRec;
    }
  return u;
}

} // namespace rcfd
