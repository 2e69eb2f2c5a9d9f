// The count behind QuietOpenMesh: OpenMesh's streams are one per process, so their state is too.
#include "tiltfield/core/internal/quiet_openmesh.hpp"

#include <OpenMesh/Core/System/omstream.hh>

#include <mutex>

namespace tf::internal {
namespace {

std::mutex quiet_mutex;
int quiet_guards = 0;

}  // namespace

QuietOpenMesh::QuietOpenMesh() {
  const std::lock_guard<std::mutex> lock(quiet_mutex);
  if (quiet_guards++ == 0) {
    omerr().disable();
    omlog().disable();
  }
}

QuietOpenMesh::~QuietOpenMesh() {
  const std::lock_guard<std::mutex> lock(quiet_mutex);
  if (--quiet_guards == 0) {
    omerr().enable();
    omlog().enable();
  }
}

}  // namespace tf::internal
