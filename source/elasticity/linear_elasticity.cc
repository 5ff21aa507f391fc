// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>

#include <algorithm>
#include <set>

namespace TKR::Elasticity
{
  using namespace dealii;

  SymmetricTensor<2, 3>
  stress(const Parameters::Material  &material,
         const SymmetricTensor<2, 3> &strain)
  {
    return material.lambda() * trace(strain) * unit_symmetric_tensor<3>() +
           2. * material.mu() * strain;
  }

  bool
  BoundaryLoads::acts_on(const types::boundary_id id) const
  {
    return tractions.count(id) || springs.count(id) ||
           traction_fields.count(id) || spring_fields.count(id);
  }

  Tensor<1, 3>
  BoundaryLoads::traction(const types::boundary_id id, const Point<3> &x) const
  {
    Tensor<1, 3> t;
    if (const auto it = tractions.find(id); it != tractions.end())
      t += it->second;
    if (const auto it = traction_fields.find(id); it != traction_fields.end())
      t += it->second(x);
    return t;
  }

  Tensor<2, 3>
  BoundaryLoads::spring(const types::boundary_id id, const Point<3> &x) const
  {
    Tensor<2, 3> S;
    if (const auto it = springs.find(id); it != springs.end())
      S += it->second;
    if (const auto it = spring_fields.find(id); it != spring_fields.end())
      S += it->second(x);
    return S;
  }

  BoundaryLoads
  linear_combination(const std::vector<BoundaryLoads> &basis,
                     const std::vector<double>        &coefficients,
                     const BoundaryLoads              &springs)
  {
    AssertDimension(basis.size(), coefficients.size());
    BoundaryLoads loads;
    loads.springs       = springs.springs;
    loads.spring_fields = springs.spring_fields;
    std::set<types::boundary_id> ids;
    for (const auto &b : basis)
      {
        for (const auto &[id, t] : b.tractions)
          ids.insert(id);
        for (const auto &[id, t] : b.traction_fields)
          ids.insert(id);
      }
    for (const types::boundary_id id : ids)
      loads.traction_fields[id] = [basis, coefficients, id](const Point<3> &x) {
        Tensor<1, 3> t;
        for (unsigned int i = 0; i < basis.size(); ++i)
          if (coefficients[i] != 0.)
            t += coefficients[i] * basis[i].traction(id, x);
        return t;
      };
    return loads;
  }

  const Parameters::Material &
  material_of(const Parameters::Materials &materials,
              const types::material_id     material_id)
  {
    return material_id == Mesh::MaterialIds::femur ? materials.femur :
                                                     materials.tibia;
  }

  LinearElasticity::LinearElasticity(
    const Triangulation<3>         &triangulation,
    const Parameters::Materials    &materials,
    const Parameters::LinearSolver &solver_parameters,
    const unsigned int              fe_degree,
    const MPI_Comm                  mpi_communicator,
    TimerOutput                    &timer)
    : materials(materials)
    , solver_parameters(solver_parameters)
    , mpi_communicator(mpi_communicator)
    , timer(timer)
    , fe(FE_Q<3>(fe_degree), 3)
    , dof_handler(triangulation)
  {}

  void
  LinearElasticity::distribute_dofs()
  {
    TimerOutput::Scope scope(timer, "distribute DoFs");
    dof_handler.distribute_dofs(fe);
    owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_dofs);
  }

  // The bilinear form is $a(u,v) = \int_\Omega \varepsilon(v) : C :
  // \varepsilon(u) + \int_{\Gamma_S} v \cdot S u$ with the material of each
  // cell and the distributed springs S; the load is
  // $\int_{\Gamma_N} t \cdot v$ for the uniform tractions $t$ given per
  // boundary id.
  void
  LinearElasticity::local_assemble(
    const typename DoFHandler<3>::active_cell_iterator &cell,
    FEValues<3>                                        &fe_values,
    FEFaceValues<3>                                    &fe_face_values,
    const BoundaryLoads                                &loads,
    FullMatrix<double>                                 &cell_matrix,
    Vector<double>                                     &cell_rhs) const
  {
    const unsigned int                 dofs_per_cell = fe.n_dofs_per_cell();
    const FEValuesExtractors::Vector   displacement(0);
    std::vector<SymmetricTensor<2, 3>> strain(dofs_per_cell);
    cell_matrix = 0;
    cell_rhs    = 0;
    fe_values.reinit(cell);
    const auto &material = material_of(materials, cell->material_id());
    for (const unsigned int q : fe_values.quadrature_point_indices())
      {
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          strain[i] = fe_values[displacement].symmetric_gradient(i, q);
        const double JxW = fe_values.JxW(q);
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const SymmetricTensor<2, 3> sigma_i = stress(material, strain[i]);
            for (unsigned int j = 0; j <= i; ++j)
              cell_matrix(i, j) += (sigma_i * strain[j]) * JxW;
          }
      }
    for (unsigned int i = 0; i < dofs_per_cell; ++i)
      for (unsigned int j = i + 1; j < dofs_per_cell; ++j)
        cell_matrix(i, j) = cell_matrix(j, i);

    local_assemble_boundary(cell,
                            fe_face_values,
                            loads,
                            &cell_matrix,
                            cell_rhs);
  }

  // The boundary terms: tractions into the right-hand side and, when
  // @p cell_matrix is given, the springs into the matrix.
  void
  LinearElasticity::local_assemble_boundary(
    const typename DoFHandler<3>::active_cell_iterator &cell,
    FEFaceValues<3>                                    &fe_face_values,
    const BoundaryLoads                                &loads,
    FullMatrix<double>                                 *cell_matrix,
    Vector<double>                                     &cell_rhs) const
  {
    const unsigned int               dofs_per_cell = fe.n_dofs_per_cell();
    const FEValuesExtractors::Vector displacement(0);
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() &&
          loads.acts_on(cell->face(f)->boundary_id()))
        {
          const auto id = cell->face(f)->boundary_id();
          fe_face_values.reinit(cell, f);
          for (const unsigned int q : fe_face_values.quadrature_point_indices())
            {
              const Point<3>    &x   = fe_face_values.quadrature_point(q);
              const Tensor<1, 3> t   = loads.traction(id, x);
              const double       JxW = fe_face_values.JxW(q);
              const Tensor<2, 3> S =
                cell_matrix ? loads.spring(id, x) : Tensor<2, 3>();
              for (unsigned int i = 0; i < dofs_per_cell; ++i)
                {
                  const Tensor<1, 3> v_i =
                    fe_face_values[displacement].value(i, q);
                  cell_rhs(i) += t * v_i * JxW;
                  if (cell_matrix)
                    for (unsigned int j = 0; j < dofs_per_cell; ++j)
                      (*cell_matrix)(i, j) +=
                        v_i * (S * fe_face_values[displacement].value(j, q)) *
                        JxW;
                }
            }
        }
  }

  void
  LinearElasticity::for_each_cell_system(
    const Mapping<3>    &mapping,
    const BoundaryLoads &loads,
    const std::function<void(const DoFHandler<3>::active_cell_iterator &,
                             const FullMatrix<double> &,
                             Vector<double> &,
                             const std::vector<types::global_dof_index> &)>
      &use,
    const std::function<bool(const DoFHandler<3>::active_cell_iterator &,
                             const std::vector<types::global_dof_index> &)>
      &select) const
  {
    FEValues<3>        fe_values(mapping,
                          fe,
                          QGauss<3>(fe.degree + 1),
                          update_gradients | update_JxW_values);
    FEFaceValues<3>    fe_face_values(mapping,
                                   fe,
                                   QGauss<2>(fe.degree + 1),
                                   update_values | update_quadrature_points |
                                     update_JxW_values);
    FullMatrix<double> cell_matrix(fe.n_dofs_per_cell(), fe.n_dofs_per_cell());
    Vector<double>     cell_rhs(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          if (select && !select(cell, dof_indices))
            continue;
          local_assemble(cell,
                         fe_values,
                         fe_face_values,
                         loads,
                         cell_matrix,
                         cell_rhs);
          use(cell, cell_matrix, cell_rhs, dof_indices);
        }
  }

  TrilinosWrappers::MPI::Vector
  LinearElasticity::load_vector(const Mapping<3>                &mapping,
                                const AffineConstraints<double> &constraints,
                                const BoundaryLoads             &loads) const
  {
    TimerOutput::Scope                   scope(timer, "assemble rhs");
    TrilinosWrappers::MPI::Vector        rhs(owned_dofs, mpi_communicator);
    FEFaceValues<3>                      fe_face_values(mapping,
                                   fe,
                                   QGauss<2>(fe.degree + 1),
                                   update_values | update_quadrature_points |
                                     update_JxW_values);
    Vector<double>                       cell_rhs(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->at_boundary())
        {
          cell_rhs = 0;
          local_assemble_boundary(cell,
                                  fe_face_values,
                                  loads,
                                  nullptr,
                                  cell_rhs);
          if (cell_rhs.l2_norm() == 0.)
            continue;
          cell->get_dof_indices(dof_indices);
          constraints.distribute_local_to_global(cell_rhs, dof_indices, rhs);
        }
    rhs.compress(VectorOperation::add);
    return rhs;
  }

  void
  LinearElasticity::compute_residual(
    const Mapping<3>                    &mapping,
    const BoundaryLoads                 &loads,
    const TrilinosWrappers::MPI::Vector &solution,
    const IndexSet                      &rows,
    TrilinosWrappers::MPI::Vector       &residual) const
  {
    TimerOutput::Scope scope(timer, "residual");
    const bool         all_rows = (rows.n_elements() == dof_handler.n_dofs());
    residual.reinit(owned_dofs, mpi_communicator);
    Vector<double> cell_u(fe.n_dofs_per_cell()), cell_Ku(fe.n_dofs_per_cell());
    for_each_cell_system(
      mapping,
      loads,
      [&](const auto &cell,
          const auto &cell_matrix,
          auto       &cell_rhs,
          const auto &dofs) {
        cell->get_dof_values(solution, cell_u);
        cell_matrix.vmult(cell_Ku, cell_u);
        cell_rhs -= cell_Ku;
        residual.add(dofs, cell_rhs);
      },
      [&](const auto &, const auto &dofs) {
        return all_rows ||
               std::any_of(dofs.begin(), dofs.end(), [&](const auto i) {
                 return rows.is_element(i);
               });
      });
    residual.compress(VectorOperation::add);
  }

  TrilinosWrappers::MPI::Vector
  LinearElasticity::make_ghosted_vector() const
  {
    return TrilinosWrappers::MPI::Vector(owned_dofs,
                                         relevant_dofs,
                                         mpi_communicator);
  }

  double
  LinearElasticity::max_displacement(
    const TrilinosWrappers::MPI::Vector &solution,
    const types::material_id             material) const
  {
    Vector<double> cell_values(fe.n_dofs_per_cell());
    double         max_norm = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->material_id() == material)
        {
          cell->get_dof_values(solution, cell_values);
          for (unsigned int node = 0;
               node < fe.base_element(0).n_dofs_per_cell();
               ++node)
            {
              double norm_square = 0;
              for (unsigned int d = 0; d < 3; ++d)
                norm_square += Utilities::fixed_power<2>(
                  cell_values(fe.component_to_system_index(d, node)));
              max_norm = std::max(max_norm, std::sqrt(norm_square));
            }
        }
    return Utilities::MPI::max(max_norm, mpi_communicator);
  }
} // namespace TKR::Elasticity
