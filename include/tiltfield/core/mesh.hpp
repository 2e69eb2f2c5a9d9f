// tiltfield: triangle meshes. One mesh type (OpenMesh TriMesh with double-precision points), free
// functions over it.
#pragma once
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

namespace tf {

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  EdgeAttributes(OpenMesh::Attributes::Status);
};
// OpenMesh's mesh has no move constructor or move assignment: std::move of a Mesh copies it, and so does
// assigning a returned one. Build a large mesh where it is kept (initialise from a returned prvalue, or
// fill one passed by reference).
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// A flat copy of a mesh for libraries that want arrays (nanoflann, Embree, FCL, Ceres).
// V: one vertex a row, mm. F: one triangle a row, indices into V, counter-clockwise seen from outside.
struct TriangleArrays {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> F;
};

// Reads STL (ASCII or binary), OBJ, OFF or PLY by extension. Throws InputError naming the file when it
// cannot be read, has an unknown extension, or has no triangles. Polygons are triangulated.
Mesh load_mesh(const std::filesystem::path& file);

// Throws InputError naming `file` unless its extension is a mesh format load_mesh and write_mesh know
// (.stl, .obj, .off, .ply, any case): lets a command refuse an output name before its long work.
void check_mesh_format(const std::filesystem::path& file);

// Writes by extension (.stl binary, .obj, .off, .ply binary); vertex colours are written when the mesh
// has them and the format carries them. Written to a temporary name and renamed.
void write_mesh(const Mesh& mesh, const std::filesystem::path& file);

// The bytes write_mesh writes for `mesh` as a .ply (binary, with its vertex colours), without writing.
size_t ply_size(const Mesh& mesh);

// Builds a mesh from arrays (V in mm, F counter-clockwise from outside).
Mesh mesh_from_arrays(const Eigen::Ref<const Eigen::MatrixX3d>& V, const Eigen::Ref<const Eigen::MatrixX3i>& F);
TriangleArrays to_arrays(const Mesh& mesh);

Eigen::AlignedBox3d bounding_box(const Mesh& mesh);

// True when every edge has exactly two faces (no boundary), i.e. the mesh can bound a solid.
bool is_closed(const Mesh& mesh);

// The number of edge-connected pieces of faces (vertices shared through a face's edges).
size_t connected_pieces(const Mesh& mesh);

// Signed volume (mm^3) by the divergence theorem; positive when the faces are oriented outward.
double signed_volume(const Mesh& mesh);

// Appends b to a (no vertex welding).
void append_mesh(Mesh& a, const Mesh& b);

// Each vertex's signed distance from a design surface (mm: + material left, - cut into the design), kept
// on the mesh as a vertex property, so that what colours a stock mesh need not be measured again by the
// report (reconstruct_stock sets it when it colours by deviation). Copies of the mesh keep it, and
// decimate_within gives it to the vertices it keeps; files and other meshes built from it do not.
void set_vertex_deviation(Mesh& mesh, const std::vector<double>& deviation_mm);
// The property's values per vertex, or empty when the mesh has none.
std::vector<double> vertex_deviation(const Mesh& mesh);

inline Eigen::Vector3d to_eigen(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
inline OpenMesh::Vec3d to_om(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace tf
