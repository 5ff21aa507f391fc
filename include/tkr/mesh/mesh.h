// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_mesh_mesh_h
#define tkr_mesh_mesh_h

#include <deal.II/base/types.h>

#include <deal.II/grid/tria.h>

#include <tkr/parameters/parameters.h>

#include <array>
#include <string>
#include <vector>

/**
 * Reading the two-body gmsh mesh and checking it. The physical groups are
 * found by name (DESIGN.md section 3) and mapped to the fixed material and
 * boundary ids below, which are the only ids the rest of the program uses.
 */
namespace TKR::Mesh
{
  /** Material ids of the two bodies after read_mesh(). */
  namespace MaterialIds
  {
    constexpr dealii::types::material_id femur = 0;
    constexpr dealii::types::material_id tibia = 1;
  } // namespace MaterialIds

  /** Boundary ids after read_mesh(); untagged faces are traction free. */
  namespace BoundaryIds
  {
    constexpr dealii::types::boundary_id free           = 0;
    constexpr dealii::types::boundary_id femur_contact  = 1;
    constexpr dealii::types::boundary_id femur_fixation = 2;
    constexpr dealii::types::boundary_id tibia_contact  = 3;
    constexpr dealii::types::boundary_id tibia_inferior = 4;
  } // namespace BoundaryIds

  /** One entry of the `$PhysicalNames` table of a gmsh file. */
  struct PhysicalGroup
  {
    int         dim;
    int         tag;
    std::string name;
  };

  /**
   * Read the `$PhysicalNames` table of an ASCII gmsh file (formats 2.2 and
   * 4.x). deal.II's GridIn keeps only the numeric tags, so the names have to
   * be read separately.
   */
  std::vector<PhysicalGroup>
  read_physical_names(const std::string &filename);

  /**
   * Read the mesh named in @p parameters into @p triangulation (empty on
   * entry; typically a parallel::shared::Triangulation), set material and
   * boundary ids from the group names, and check it with check_mesh().
   * Throws ExcInputError with a message naming the file and the problem if
   * the file cannot be read, a group is missing or empty, or a cell is
   * inverted.
   */
  void
  read_mesh(const Parameters::Mesh   &parameters,
            dealii::Triangulation<3> &triangulation);

  /**
   * Check that both bodies and all four surfaces are present and that no
   * cell has a non-positive Jacobian determinant at any vertex (inverted or
   * twisted cell). @p filename is used in the messages only.
   */
  void
  check_mesh(const dealii::Triangulation<3> &triangulation,
             const std::string              &filename);

  /**
   * The smallest Jacobian determinant of the trilinear map of a hexahedron
   * with the vertices @p x (deal.II's lexicographic order) at its eight
   * vertices: the triple products of the edges that leave each vertex
   * (mm^3). Positive for a valid cell; zero or negative for a collapsed,
   * twisted or inverted one.
   */
  double
  min_vertex_jacobian(const std::array<dealii::Point<3>, 8> &x);

  /**
   * The smallest scaled corner Jacobian of a hexahedron with the vertices
   * @p x (deal.II order): at every corner, the determinant of the three
   * edges leaving it divided by the product of their lengths (1 for a
   * cube, 0 for a degenerate corner, negative for an inverted one); the
   * measure gmsh and meshes/gen/check_msh.py report.
   */
  double
  min_scaled_jacobian(const std::array<dealii::Point<3>, 8> &x);

  /** Volumes (mm^3) and face areas (mm^2) of the tagged parts of a mesh. */
  struct MeshStatistics
  {
    double       femur_volume     = 0;
    double       tibia_volume     = 0;
    double       boundary_area[5] = {0, 0, 0, 0, 0};
    unsigned int femur_cells = 0, tibia_cells = 0;
    unsigned int n_vertices = 0;
    /**
     * Per boundary id: the smallest scaled Jacobian (min_scaled_jacobian())
     * of the cells with a face on that part (1 if none).
     */
    double min_quality[5] = {1, 1, 1, 1, 1};
  };

  /** Measure volumes and areas with the bilinear (Q1) geometry. */
  MeshStatistics
  compute_statistics(const dealii::Triangulation<3> &triangulation);

  /** Which vertices belong to a cell of material @p material_id (by
   *  vertex index). */
  std::vector<bool>
  material_vertices(const dealii::Triangulation<3>  &triangulation,
                    const dealii::types::material_id material_id);

  /** The name of a boundary id (for messages). */
  std::string
  boundary_name(const dealii::types::boundary_id id);
} // namespace TKR::Mesh

#endif
