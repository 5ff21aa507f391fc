// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// GaitCycle: the exchange of the steps' results between the step groups
// after a cycle, and the step of the largest load.

#include <deal.II/base/mpi.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/problems/gait_cycle.h>

#include <algorithm>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /**
     * A step's relative motion, report and end state, and the lengths of
     * its record's per-node arrays (which go as plain numbers: see
     * gather_steps()), for the exchange.
     */
    struct StepResult
    {
      unsigned int                 step = 0;
      Gait::RelativeMotion         motion;
      Wear::StepRecord::ArraySizes n_nodes = {};
      Gait::StepReport             report;
      Gait::StepStart              start;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &step &motion &n_nodes &report &start;
      }
    };
  } // namespace

  // Each step's results are taken from the one rank that lists it (the
  // root of the step group that solved it; the others list none). The
  // records' per-node arrays, nearly all of the bytes, go in one exchange
  // of numbers, the rest through serialization.
  void
  GaitCycle::gather_steps(const std::vector<unsigned int> &own_steps)
  {
    std::vector<StepResult> mine;
    std::vector<double>     my_arrays;
    for (const unsigned int step : own_steps)
      {
        StepResult result;
        result.step    = step;
        result.motion  = records[step].motion;
        result.n_nodes = records[step].pack_arrays(my_arrays);
        result.report  = reports[step];
        result.start   = starts[step];
        mine.push_back(std::move(result));
      }
    std::vector<int>          offsets;
    const std::vector<double> arrays =
      all_gather_values(my_arrays, model.world(), &offsets);
    const auto all = all_gather_objects(model.world(), mine);
    for (std::size_t rank = 0; rank < all.size(); ++rank)
      {
        std::size_t position = offsets[rank];
        for (const auto &result : all[rank])
          {
            Wear::StepRecord &record = records[result.step];
            record.motion            = result.motion;
            record.unpack_arrays(result.n_nodes, arrays, position);
            reports[result.step] = result.report;
            starts[result.step]  = result.start;
          }
        AssertThrow(position == static_cast<std::size_t>(offsets[rank + 1]),
                    ExcInternalError());
      }
  }

  unsigned int
  GaitCycle::peak_load_step() const
  {
    const auto columns = protocol->input_columns();
    const auto axial =
      std::find(columns.begin(), columns.end(), "axial_force_N");
    const auto load = [&](const Gait::StepReport &report) {
      return axial != columns.end() ?
               report.input.values[axial - columns.begin()] :
               report.contact_force;
    };
    return std::max_element(reports.begin(),
                            reports.end(),
                            [&](const auto &a, const auto &b) {
                              return load(a) < load(b);
                            }) -
           reports.begin();
  }

} // namespace TKR::Problems
