// tiltfield core (internal): OpenMesh's messages off for a scope.
//
// OpenMesh reports refused faces (non-manifold input we handle ourselves) and its writers' notes on
// process-wide streams (omerr, omlog). A QuietOpenMesh silences both while it lives. Guards nest and may
// overlap across threads: they are counted under a lock, and the streams come back when the last one
// ends, also when an exception leaves its scope. Not part of the API.
#pragma once

namespace tf::internal {

class QuietOpenMesh {
 public:
  QuietOpenMesh();
  ~QuietOpenMesh();
  QuietOpenMesh(const QuietOpenMesh&) = delete;
  QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;
};

}  // namespace tf::internal
