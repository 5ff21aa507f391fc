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

#include <deal.II/base/numbers.h>

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
