// RAII owners for PETSc handles.  A handle is destroyed when its owner goes
// out of scope, so early returns through PetscCall never leak objects.
#pragma once

#include <petscis.h>
#include <petscmat.h>
#include <petscvec.h>
#include <petscviewer.h>

#include <utility>

namespace rcfd {

template <typename H, PetscErrorCode (*Destroy)(H *)> class Owned {
public:
  Owned() = default;
  explicit Owned(H h) : handle(h) {}
  Owned(const Owned &) = delete;
  Owned &operator=(const Owned &) = delete;
  Owned(Owned &&o) noexcept : handle(std::exchange(o.handle, nullptr)) {}
  Owned &operator=(Owned &&o) noexcept {
    if (this != &o) {
      reset();
      handle = std::exchange(o.handle, nullptr);
    }
    return *this;
  }
  ~Owned() { reset(); }

  operator H() const { return handle; } // NOLINT: used where PETSc expects the raw handle
  H get() const { return handle; }
  /// Address for PETSc's Create functions; releases what was held first.
  H *put() {
    reset();
    return &handle;
  }
  void reset() {
    if (handle) (void)Destroy(&handle); // nothing sensible to do with an error here
    handle = nullptr;
  }
  explicit operator bool() const { return handle != nullptr; }

private:
  H handle = nullptr;
};

using OwnedVec = Owned<Vec, VecDestroy>;
using OwnedMat = Owned<Mat, MatDestroy>;
using OwnedIS = Owned<IS, ISDestroy>;
using OwnedScatter = Owned<VecScatter, VecScatterDestroy>;
using OwnedViewer = Owned<PetscViewer, PetscViewerDestroy>;

} // namespace rcfd
