// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/mpi.h>

#include <tkr/wear/step_record.h>

namespace TKR::Wear
{
  using namespace dealii;

  StepRecord
  make_step_record(const Mortar::MortarCoupling &coupling,
                   const Contact::ContactState  &state,
                   const Gait::RigidMotion      &femur_motion,
                   const Tensor<1, 3>           &tibia_translation)
  {
    const auto        &nodes = coupling.slave_nodes();
    const unsigned int n     = nodes.size();
    StepRecord         record;
    record.femur_motion = femur_motion;
    record.pressure.assign(n, 0.);
    record.femur_point.assign(n, Point<3>());
    record.displacement.assign(n, Tensor<1, 3>());
    record.normal.assign(n, Tensor<1, 3>());
    for (unsigned int j = 0; j < n; ++j)
      {
        record.normal[j] = nodes[j].normal;
        if (j < state.displacement.size())
          record.displacement[j] = state.displacement[j] + tibia_translation;
        else
          record.displacement[j] = tibia_translation;
        if (j < state.active.size() && state.active[j])
          {
            record.pressure[j] = std::max(0., state.pressure[j]);
            record.femur_point[j] =
              femur_motion.inverse(nodes[j].master_point + tibia_translation);
          }
      }
    return record;
  }

  namespace
  {
    /** A step's record, report and end state, for the exchange. */
    struct StepResult
    {
      unsigned int step = 0;
      StepRecord   record;
      StepReport   report;
      StepStart    start;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &step &record &report &start;
      }
    };
  } // namespace

  void
  gather_steps(const std::vector<unsigned int> &own_steps,
               std::vector<StepRecord>         &records,
               std::vector<StepReport>         &reports,
               std::vector<StepStart>          &starts,
               const MPI_Comm                   communicator)
  {
    std::vector<StepResult> mine;
    for (const unsigned int step : own_steps)
      mine.push_back({step, records[step], reports[step], starts[step]});
    for (const auto &from_rank : Utilities::MPI::all_gather(communicator, mine))
      for (const auto &result : from_rank)
        {
          records[result.step] = result.record;
          reports[result.step] = result.report;
          starts[result.step]  = result.start;
        }
  }
} // namespace TKR::Wear
