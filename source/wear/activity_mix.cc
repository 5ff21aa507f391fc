// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/wear/activity_mix.h>

namespace TKR::Wear
{
  namespace
  {
    /** @p sum += @p share x @p values. */
    void
    add_scaled(std::vector<double>       &sum,
               const double               share,
               const std::vector<double> &values)
    {
      sum.resize(values.size(), 0.);
      for (unsigned int j = 0; j < values.size(); ++j)
        sum[j] += share * values[j];
    }
  } // namespace

  CycleWear
  mix_cycle_wear(const std::vector<CycleWear> &wear,
                 const std::vector<double>    &shares)
  {
    AssertThrow(!wear.empty() && wear.size() == shares.size(),
                dealii::ExcInternalError());
    if (wear.size() == 1 && shares[0] == 1.)
      return wear[0];
    CycleWear mix;
    mix.fields = wear[0].fields;
    for (auto &[name, values] : mix.fields)
      values.assign(values.size(), 0.);
    const unsigned int  n_nodes = wear[0].depth.size();
    std::vector<double> best_work(n_nodes, -1.);
    mix.cross_shear.resize(n_nodes);
    for (unsigned int a = 0; a < wear.size(); ++a)
      {
        const double share = shares[a];
        AssertThrow(wear[a].depth.size() == n_nodes &&
                      wear[a].cross_shear.size() == n_nodes &&
                      wear[a].fields.size() == mix.fields.size(),
                    dealii::ExcInternalError());
        add_scaled(mix.depth, share, wear[a].depth);
        add_scaled(mix.slip, share, wear[a].slip);
        for (unsigned int f = 0; f < mix.fields.size(); ++f)
          add_scaled(mix.fields[f].second, share, wear[a].fields[f].second);
        for (unsigned int j = 0; j < n_nodes; ++j)
          {
            const CrossShear &cs   = wear[a].cross_shear[j];
            const double      work = share * cs.work;
            mix.cross_shear[j].work += work;
            mix.cross_shear[j].ratio += work * cs.ratio;
            if (work > best_work[j])
              {
                best_work[j]                   = work;
                mix.cross_shear[j].orientation = cs.orientation;
              }
          }
      }
    for (auto &cs : mix.cross_shear)
      cs.ratio = cs.work > 0 ? cs.ratio / cs.work : 0.;
    return mix;
  }
} // namespace TKR::Wear
