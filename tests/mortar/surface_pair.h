// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The set-up the mortar tests share: a two-body triangulation's Q1 vector
// DoFs and its contact surfaces.

#ifndef tkr_tests_mortar_surface_pair_h
#define tkr_tests_mortar_surface_pair_h

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>

#include <deal.II/grid/tria.h>

#include <tkr/mesh/mesh.h>
#include <tkr/mortar/contact_surface.h>
#include <tkr/mortar/mortar_coupling.h>

#include <deal.II/base/numbers.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

/** Read meshes/@p name (a path below meshes/) with the default groups. */
inline void
read_test_mesh(const std::string &name, dealii::Triangulation<3> &triangulation)
{
  TKR::Mesh::read_mesh(TKR::Parameters::Mesh::with_default_groups(
                         std::string(SOURCE_DIR) + "/../../meshes/" + name),
                       triangulation);
}

/** The vertices of @p triangulation with the femur flexed by @p degrees
 *  about the TKR A flexion axis (x through y = -2, z = 53.001), then moved
 *  by @p shift. */
inline std::vector<dealii::Point<3>>
femur_moved(const dealii::Triangulation<3> &triangulation,
            const double                    degrees,
            const dealii::Tensor<1, 3>     &shift)
{
  std::vector<dealii::Point<3>> x = triangulation.get_vertices();
  const std::vector<bool>       is_femur =
    TKR::Mesh::material_vertices(triangulation, TKR::Mesh::MaterialIds::femur);
  const double a = degrees * dealii::numbers::PI / 180.;
  for (unsigned int v = 0; v < x.size(); ++v)
    if (is_femur[v])
      {
        const double y = x[v][1] + 2., z = x[v][2] - 53.001;
        x[v][1] = -2. + std::cos(a) * y - std::sin(a) * z;
        x[v][2] = 53.001 + std::sin(a) * y + std::cos(a) * z;
        x[v] += shift;
      }
  return x;
}

/** The smallest mean gap g_j / D_jj (mm) of a covered node. */
inline double
smallest_gap(const TKR::Mortar::MortarCoupling &coupling)
{
  double result = 1e300;
  for (const auto &node : coupling.slave_nodes())
    if (node.covered)
      result = std::min(result, node.weighted_gap / node.D);
  return result;
}

/** The shift of the femur flexed by @p degrees (femur_moved()) that lowers
 *  it until it touches the tibia (the smallest mean gap of @p coupling
 *  vanishes), and then by @p depth (mm) more. */
inline dealii::Tensor<1, 3>
femur_touching(const dealii::Triangulation<3> &triangulation,
               TKR::Mortar::MortarCoupling    &coupling,
               const double                    degrees,
               const double                    search_distance,
               const double                    depth = 0)
{
  dealii::Tensor<1, 3> shift;
  coupling.reinit(femur_moved(triangulation, degrees, shift), search_distance);
  shift[2] = -smallest_gap(coupling) - depth;
  return shift;
}

/** @p check(mesh name, degrees) for the coarse TKR A and its mesh-implant
 *  output, the femur flexed by 0 and 30 degrees. */
template <typename Check>
void
for_each_tkr_a_pose(const Check &check)
{
  for (const std::string name : {"tkr-a-coarse.msh", "tkr-a-implant.msh"})
    for (const double degrees : {0., 30.})
      check(name, degrees);
}

/** The Q1 vector DoFs of @p triangulation and its contact surfaces:
 *  tibia_contact (slave) and femur_contact (master). */
struct SurfacePair
{
  explicit SurfacePair(const dealii::Triangulation<3> &triangulation)
    : fe(dealii::FE_Q<3>(1), 3)
    , dof_handler(triangulation)
    , slave(distributed(dof_handler, fe), TKR::Mesh::BoundaryIds::tibia_contact)
    , master(dof_handler, TKR::Mesh::BoundaryIds::femur_contact)
  {}

  const dealii::FESystem<3>         fe;
  dealii::DoFHandler<3>             dof_handler;
  const TKR::Mortar::ContactSurface slave, master;

private:
  static const dealii::DoFHandler<3> &
  distributed(dealii::DoFHandler<3> &dof_handler, const dealii::FESystem<3> &fe)
  {
    dof_handler.distribute_dofs(fe);
    return dof_handler;
  }
};

#endif
