// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_stress_postprocessor_h
#define tkr_elasticity_stress_postprocessor_h

#include <deal.II/numerics/data_postprocessor.h>

#include <tkr/parameters/parameters.h>

namespace TKR::Elasticity
{
  /**
   * Writes the Cauchy stress tensor (MPa) of a displacement field, with the
   * material of each cell, as a tensor field "stress" for ParaView.
   */
  class StressPostprocessor : public dealii::DataPostprocessorTensor<3>
  {
  public:
    explicit StressPostprocessor(const Parameters::Materials &materials);

    void
    evaluate_vector_field(
      const dealii::DataPostprocessorInputs::Vector<3> &inputs,
      std::vector<dealii::Vector<double>> &computed_quantities) const override;

  private:
    const Parameters::Materials materials;
  };

  /** The von Mises equivalent stress (MPa) as a scalar field. */
  class VonMisesPostprocessor : public dealii::DataPostprocessorScalar<3>
  {
  public:
    explicit VonMisesPostprocessor(const Parameters::Materials &materials);

    void
    evaluate_vector_field(
      const dealii::DataPostprocessorInputs::Vector<3> &inputs,
      std::vector<dealii::Vector<double>> &computed_quantities) const override;

  private:
    const Parameters::Materials materials;
  };
} // namespace TKR::Elasticity

#endif
