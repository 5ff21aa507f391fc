// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_cross_shear_laws_h
#define tkr_wear_cross_shear_laws_h

#include <tkr/wear/tables.h>
#include <tkr/wear/wear_law.h>

namespace TKR::Wear
{
  /**
   * The entries of a law with a coefficient over the cross-shear
   * (`Wear/Archard cs`, `Wear/Area`).
   */
  struct CrossShearLawParameters
  {
    /** The CSV table of the coefficient over the cross-shear. */
    std::string cross_shear_table;
    /** A factor on the table's coefficient (`Table scale`; what a
     *  calibration fits, doc/calibration.md). */
    double table_scale = 1;
  };

  /**
   * The laws that depend on each node's cross-shear over the cycle
   * (cycle_cross_shear(), doc/wear.md "Cross-shear"): analyse_cycle()
   * keeps the ratios, node_fields() has nothing beyond what every run
   * writes.
   */
  class CrossShearLaw : public WearLaw
  {
  public:
    void
    analyse_cycle(const CycleSliding            &sliding,
                  const std::vector<CrossShear> &cross_shear) override;

  protected:
    /** The cross-shear ratio of every node over the cycle analysed last. */
    std::vector<double> ratio;
  };

  /**
   * Archard's law with a wear coefficient that depends on the node's
   * cross-shear over the cycle and optionally on the contact pressure
   * (`Wear law = archard_cs`, doc/wear.md): the depth of an interval is
   * (k(CS, p_a) p_a |s_a| + k(CS, p_b) p_b |s_b|) / 2, as ArchardWear's
   * with k from the table (column k_mm3_per_Nm, in mm^3/(N m)).
   */
  class ArchardCrossShearWear : public CrossShearLaw
  {
  public:
    /** k = @p scale x the table's value. */
    ArchardCrossShearWear(const CrossShearTable &k_per_metre,
                          const double           scale = 1);

    double
    interval_depth(const CycleSliding &sliding,
                   const unsigned int  i,
                   const unsigned int  j) const override;

  protected:
    std::string
    law_description() const override;

  private:
    /** k in mm^3/(N m) over cross-shear (and pressure in MPa). */
    const CrossShearTable k_per_metre;
    const double          scale;
  };

  /**
   * The contact-area law (`Wear law = area`, doc/wear.md): worn volume =
   * C(CS) x contact area x sliding distance, i.e. a node's depth over an
   * interval is C(CS) times its slip distance there
   * (IntervalSliding::slip_distance()), whatever the pressure; C is
   * dimensionless (column C of the table).
   */
  class AreaWear : public CrossShearLaw
  {
  public:
    /** C = @p scale x the table's value. */
    AreaWear(const CrossShearTable &c, const double scale = 1);

    double
    interval_depth(const CycleSliding &sliding,
                   const unsigned int  i,
                   const unsigned int  j) const override;

  protected:
    std::string
    law_description() const override;

  private:
    const CrossShearTable c;
    const double          scale;
  };
} // namespace TKR::Wear

#endif
