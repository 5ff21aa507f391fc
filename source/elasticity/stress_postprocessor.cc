// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/dofs/dof_handler.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/elasticity/stress_postprocessor.h>

namespace TKR::Elasticity
{
  using namespace dealii;

  namespace
  {
    /** The stress at evaluation point @p q of a postprocessor input. */
    SymmetricTensor<2, 3>
    stress_at(const Parameters::Materials              &materials,
              const DataPostprocessorInputs::Vector<3> &inputs,
              const unsigned int                        q)
    {
      const auto   cell = inputs.template get_cell<3>();
      Tensor<2, 3> gradient;
      for (unsigned int c = 0; c < 3; ++c)
        gradient[c] = inputs.solution_gradients[q][c];
      return stress(material_of(materials, cell->material_id()),
                    symmetrize(gradient));
    }
  } // namespace

  StressPostprocessor::StressPostprocessor(
    const Parameters::Materials &materials)
    : DataPostprocessorTensor<3>("stress", update_gradients)
    , materials(materials)
  {}

  void
  StressPostprocessor::evaluate_vector_field(
    const DataPostprocessorInputs::Vector<3> &inputs,
    std::vector<Vector<double>>              &computed_quantities) const
  {
    for (unsigned int q = 0; q < computed_quantities.size(); ++q)
      {
        const SymmetricTensor<2, 3> sigma = stress_at(materials, inputs, q);
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            computed_quantities[q](Tensor<2, 3>::component_to_unrolled_index(
              TableIndices<2>(i, j))) = sigma[i][j];
      }
  }

  VonMisesPostprocessor::VonMisesPostprocessor(
    const Parameters::Materials &materials)
    : DataPostprocessorScalar<3>("von_mises_stress", update_gradients)
    , materials(materials)
  {}

  void
  VonMisesPostprocessor::evaluate_vector_field(
    const DataPostprocessorInputs::Vector<3> &inputs,
    std::vector<Vector<double>>              &computed_quantities) const
  {
    for (unsigned int q = 0; q < computed_quantities.size(); ++q)
      {
        const SymmetricTensor<2, 3> s =
          deviator(stress_at(materials, inputs, q));
        computed_quantities[q](0) = std::sqrt(1.5 * (s * s));
      }
  }
} // namespace TKR::Elasticity
