// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_step_record_h
#define tkr_wear_step_record_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <tkr/contact/contact_state.h>
#include <tkr/gait/rigid_motion.h>
#include <tkr/mortar/mortar_coupling.h>

#include <boost/serialization/vector.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace TKR::Wear
{
  /**
   * What one gait step leaves for the wear computation, in the tibia's
   * frame: the femur's rigid motion relative to the tibia, and per slave
   * (`tibia_contact`) node the contact pressure (0 where not in contact),
   * the femur material point it touches (in the femur's reference
   * configuration), the node's elastic displacement and its normal.
   */
  struct StepRecord
  {
    Gait::RelativeMotion              motion;
    std::vector<double>               pressure;
    std::vector<dealii::Point<3>>     femur_point;
    std::vector<dealii::Tensor<1, 3>> displacement;
    std::vector<dealii::Tensor<1, 3>> normal;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &motion &pressure &femur_point &displacement &normal;
    }

    /** The lengths of pressure, femur_point, displacement and normal. */
    using ArraySizes = std::array<unsigned int, 4>;

    /**
     * The per-node arrays as plain numbers (every field but motion, which
     * serialize() covers too): their lengths, and appended to @p values.
     * For an exchange that sends nearly all of a record's bytes without
     * serialising them (see GaitCycle::gather_steps()).
     */
    ArraySizes
    pack_arrays(std::vector<double> &values) const;

    /**
     * Read the per-node arrays of lengths @p sizes written by pack_arrays()
     * from @p values, from @p position on (advanced past them).
     */
    void
    unpack_arrays(const ArraySizes          &sizes,
                  const std::vector<double> &values,
                  std::size_t               &position);
  };

  /**
   * The record of a contact solve on a coupling made in the tibia's frame
   * with the femur moved by @p motion: pressures of the active nodes, the
   * tibia's elastic displacement, and as femur material point the mortar
   * projection of each node mapped back through @p motion.
   */
  StepRecord
  make_step_record(const Mortar::MortarCoupling &coupling,
                   const Contact::ContactState  &state,
                   const Gait::RelativeMotion   &motion);
} // namespace TKR::Wear

#endif
