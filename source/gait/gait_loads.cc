// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/numbers.h>
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>

#include <deal.II/grid/grid_tools.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/gait_loads.h>
#include <tkr/mesh/mesh.h>

namespace TKR::Gait
{
  using namespace dealii;

  InferiorSurface
  measure_inferior_surface(const Triangulation<3> &triangulation)
  {
    const FE_Q<3>      fe(1);
    const MappingQ1<3> mapping;
    FEFaceValues<3>    fe_face_values(mapping,
                                   fe,
                                   QGauss<2>(3),
                                   update_quadrature_points |
                                     update_JxW_values);
    InferiorSurface    surface;
    double             x_min = 1e300, x_max = -1e300;
    // Two passes: the centroid first, then the moments about it.
    for (unsigned int pass = 0; pass < 2; ++pass)
      for (const auto &cell : triangulation.active_cell_iterators())
        {
          if (pass == 0 && cell->material_id() == Mesh::MaterialIds::tibia)
            for (const auto v : cell->vertex_indices())
              {
                x_min = std::min(x_min, cell->vertex(v)[0]);
                x_max = std::max(x_max, cell->vertex(v)[0]);
              }
          for (const auto f : cell->face_indices())
            if (cell->face(f)->at_boundary() &&
                cell->face(f)->boundary_id() ==
                  Mesh::BoundaryIds::tibia_inferior)
              {
                fe_face_values.reinit(cell, f);
                for (const unsigned int q :
                     fe_face_values.quadrature_point_indices())
                  {
                    const Point<3> &x   = fe_face_values.quadrature_point(q);
                    const double    JxW = fe_face_values.JxW(q);
                    if (pass == 0)
                      {
                        surface.area += JxW;
                        surface.centroid += JxW * x;
                        continue;
                      }
                    const double dx = x[0] - surface.centroid[0];
                    const double dy = x[1] - surface.centroid[1];
                    const double r2 = dx * dx + dy * dy;
                    surface.I_xx += dx * dx * JxW;
                    surface.I_yy += dy * dy * JxW;
                    surface.J += r2 * JxW;
                    surface.R4 += r2 * r2 * JxW;
                  }
              }
          if (pass == 0 && cell == triangulation.last_active())
            surface.centroid /= surface.area;
        }
    surface.width = x_max - x_min;
    return surface;
  }

  GaitLoads::GaitLoads(const Parameters::Gait &parameters,
                       const Restraints       &restraints,
                       const InferiorSurface  &surface)
    : parameters(parameters)
    , restraint(restraints)
    , surface(surface)
  {
    AssertThrow(surface.area > 0 && surface.J > 0,
                ExcInputError("The tibia_inferior surface has no area."));
  }

  Tensor<1, 3>
  GaitLoads::force(const GaitState &state) const
  {
    // A femur offset a moves the AP restraint's neutral tibia position to
    // -a: the springs' force -K (d + a) is -K d plus the constant -K a.
    return Tensor<1, 3>(
      {0.,
       restraint.ap_force_sign * state.ap_force -
         restraint.ap_spring_stiffness * parameters.femur_ap_offset,
       state.axial_force});
  }

  Tensor<1, 3>
  GaitLoads::moment(const GaitState &state) const
  {
    // The axial force F_z at x_c + e has the moment -e F_z about +y; the IE
    // torque (N m -> N mm) acts about -z for internal rotation if medial is
    // +x.
    const double e = parameters.medial_direction *
                     parameters.axial_load_offset * surface.width;
    return Tensor<1, 3>({0.,
                         -e * state.axial_force,
                         -parameters.medial_direction *
                           restraint.ie_torque_sign * 1e3 * state.ie_torque});
  }

  // With dx, dy measured from the centroid: the traction
  //   t_z = F/A + (F e) dx / I_xx        carries F_z and the offset moment,
  //   t_y = F_AP / A                     the AP force,
  //   t   = T (-dy, dx, 0) / J           the torque T about z,
  // each given here for a unit force or torque.
  std::vector<Elasticity::BoundaryLoads>
  GaitLoads::traction_basis() const
  {
    const double e = parameters.medial_direction *
                     parameters.axial_load_offset * surface.width;
    const double   A = surface.area, I_xx = surface.I_xx, J = surface.J;
    const Point<3> c  = surface.centroid;
    const auto     id = Mesh::BoundaryIds::tibia_inferior;
    std::vector<Elasticity::BoundaryLoads> basis(3);
    basis[0].traction_fields[id] = [=](const Point<3> &x) {
      return Tensor<1, 3>({0., 0., 1. / A + e * (x[0] - c[0]) / I_xx});
    };
    basis[1].tractions[id]       = Tensor<1, 3>({0., 1. / A, 0.});
    basis[2].traction_fields[id] = [=](const Point<3> &x) {
      return Tensor<1, 3>({-(x[1] - c[1]) / J, (x[0] - c[0]) / J, 0.});
    };
    return basis;
  }

  std::vector<double>
  GaitLoads::resultants(const GaitState &state) const
  {
    return {force(state)[2], force(state)[1], moment(state)[2]};
  }

  Elasticity::BoundaryLoads
  GaitLoads::loads(const GaitState &state) const
  {
    return Elasticity::linear_combination(traction_basis(),
                                          resultants(state),
                                          springs());
  }

  // The springs S = k_x e_x e_x + k_y e_y e_y + beta w w^T with
  // w = (-dy, dx, 0) have the rigid-body stiffnesses k_AP in y and k_IE
  // against a rotation about z once k_y and beta are chosen as below.
  // A rotation spring beta w w^T also resists translations (by beta I_yy
  // in x and beta I_xx in y). The y spring is reduced by that amount so
  // that the AP and IE stiffnesses are exact; in x the by-product adds to
  // the ML spring (documented in doc/gait.md).
  Elasticity::BoundaryLoads
  GaitLoads::springs() const
  {
    const double   A    = surface.area;
    const Point<3> c    = surface.centroid;
    const double   k_x  = parameters.ml_spring_stiffness / A;
    const double   K_ap = restraint.ap_spring_stiffness;
    const double   K_ie = restraint.ie_spring_stiffness * 180. / numbers::PI;
    const double   beta =
      std::max(0.,
               (K_ie - k_x * surface.I_yy - K_ap * surface.I_xx / A) /
                 (surface.R4 - surface.I_xx * surface.I_xx / A));
    const double k_y = std::max(0., (K_ap - beta * surface.I_xx) / A);
    Elasticity::BoundaryLoads loads;
    loads.spring_fields[Mesh::BoundaryIds::tibia_inferior] =
      [=](const Point<3> &x) {
        const Tensor<1, 3> w({-(x[1] - c[1]), x[0] - c[0], 0.});
        Tensor<2, 3>       S = beta * outer_product(w, w);
        S[0][0] += k_x;
        S[1][1] += k_y;
        return S;
      };
    return loads;
  }

  namespace
  {
    /** -(k_beyond - k) (|x| - range) sign(x) outside the range, else 0. */
    double
    excess(const double x,
           const double range,
           const double k,
           const double k_beyond)
    {
      const double beyond = std::max(0., std::abs(x) - range);
      return -(k_beyond - k) * beyond * (x < 0 ? -1. : 1.);
    }
  } // namespace

  double
  GaitLoads::ap_restraint_excess(const double d) const
  {
    return excess(d + parameters.femur_ap_offset,
                  restraint.ap_spring_range,
                  restraint.ap_spring_stiffness,
                  restraint.ap_spring_stiffness_beyond);
  }

  double
  GaitLoads::ie_restraint_excess(const double theta) const
  {
    return excess(theta,
                  restraint.ie_spring_range,
                  restraint.ie_spring_stiffness,
                  restraint.ie_spring_stiffness_beyond);
  }

  Elasticity::BoundaryLoads::TractionField
  GaitLoads::restraint_traction(const double force_y,
                                const double torque_z) const
  {
    const auto loads = Elasticity::linear_combination(traction_basis(),
                                                      {0., force_y, torque_z},
                                                      {});
    return loads.traction_fields.at(Mesh::BoundaryIds::tibia_inferior);
  }

  RigidMotion
  GaitLoads::femur_motion(const GaitState &state) const
  {
    return RigidMotion::rotation_about(0,
                                       state.flexion,
                                       parameters.flexion_axis_point);
  }
} // namespace TKR::Gait
