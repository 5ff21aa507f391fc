// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_wear_law_h
#define tkr_wear_wear_law_h

#include <tkr/base/registry.h>
#include <tkr/parameters/parameters.h>
#include <tkr/wear/cross_shear.h>
#include <tkr/wear/sliding.h>
#include <tkr/wear/tables.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace TKR::Wear
{
  /** Named per-node fields of a law (e.g. cross-shear), for the output. */
  using NodeFields = std::vector<std::pair<std::string, std::vector<double>>>;

  /**
   * The wear of one gait cycle, node by node (`tibia_contact` nodes, in
   * the order of the mortar coupling's slave nodes).
   */
  struct CycleWear
  {
    /** Wear depth of every node over the cycle (mm). */
    std::vector<double> depth;
    /** Wear depth of every node over each interval (mm; [interval][node]). */
    std::vector<std::vector<double>> interval_depth;
    /** Slip distance of every node over each interval (mm; [interval][node]).
     */
    std::vector<std::vector<double>> interval_slip;
    /** Slip distance of every node over the cycle (mm). */
    std::vector<double> slip;
    /** The law's own per-node quantities of the cycle (WearLaw::node_fields()).
     */
    NodeFields fields;
    /** The cross-shear of every node over the cycle (computed once, for
     *  every law: the laws over it use it, and the run reports it). */
    std::vector<CrossShear> cross_shear;
  };

  /**
   * A wear law (DESIGN.md section 10): how the sliding of a gait cycle
   * wears the insert. Two phases: analyse_cycle() passes over the whole
   * cycle for per-node quantities that need it (e.g. the cross-shear of
   * the node's sliding path; nothing for Archard's law), then
   * interval_depth() gives the wear of one node over one interval. The
   * wear of a block of cycles is the law's job too (effective_cycles():
   * e.g. a run-in factor integrated from cycle N to N + n_Delta). Units
   * are converted once, in the law's constructor. cycle_wear() runs both
   * phases and is what the driver calls: every wear number of a run (the
   * block's wear, the step VTU fields, wear area and depth) comes from it.
   *
   * A new law is one class behind this interface that registers itself
   * (a WearLawPlugin, WearLaws::add() in its .cc file): nothing else
   * names the laws.
   */
  class WearLaw
  {
  public:
    virtual ~WearLaw() = default;

    /** One line for the screen: the law and its constants with units, and
     *  the run-in if there is one. */
    std::string
    description() const;

    /**
     * Phase 1: per-node quantities over the whole cycle @p sliding (whose
     * nodes' @p cross_shear is given), kept for interval_depth() and
     * node_fields(). Nothing by default.
     */
    virtual void
    analyse_cycle(const CycleSliding            &sliding,
                  const std::vector<CrossShear> &cross_shear);

    /**
     * Phase 2: the wear depth (mm) of node @p j over interval @p i of the
     * cycle @p sliding (analysed last).
     */
    virtual double
    interval_depth(const CycleSliding &sliding,
                   const unsigned int  i,
                   const unsigned int  j) const = 0;

    /**
     * The number of cycles of wear at the rate of the cycle computed at
     * cycle @p first_cycle that a block of @p n_cycles cycles from there
     * adds: @p n_cycles without a run-in, the exact integral of the run-in
     * factor over the block with one.
     */
    double
    effective_cycles(const double first_cycle, const double n_cycles) const;

    /**
     * Multiply the wear rate by the cycle-dependent @p factor (the run-in
     * of @p file, read_run_in()) from now on.
     */
    void
    set_run_in(const PiecewiseLinear &factor, const std::string &file);

    /** Compute the cross-shear by @p definition (`Wear/Cross-shear
     *  definition`) from now on. */
    void
    set_cross_shear_definition(const CrossShearDefinition definition)
    {
      cross_shear_definition = definition;
    }

    /** The run-in factor over the cycle count (empty without a run-in). */
    const PiecewiseLinear &
    get_run_in() const
    {
      return run_in;
    }

    /** The law's per-node quantities of the cycle analysed last. */
    virtual NodeFields
    node_fields() const;

    /** Both phases over the cycle @p sliding. */
    CycleWear
    cycle_wear(const CycleSliding &sliding);

  protected:
    /** The law and its constants with units, for description(). */
    virtual std::string
    law_description() const = 0;

  private:
    /** The run-in factor over the cycle count (empty: none) and its file. */
    PiecewiseLinear run_in;
    std::string     run_in_file;
    /** How cycle_wear() computes each node's cross-shear. */
    CrossShearDefinition cross_shear_definition =
      CrossShearDefinition::work_tensor;
  };

  /**
   * A wear law as a plugin (Registry): the name that selects it in
   * `Wear/Wear law`, the phrase that documents it there, its own entries
   * (`Wear/<subsection>`, e.g. `Wear/Archard`; ModelEntries, with what
   * it lacks and the entry that scales its rate), and how it is made from
   * the wear parameters and its own entries as parsed (a std::any of its
   * entries' type; empty without entries). Each law's .cc file registers
   * its own (WearLaws::add()) and writes its name once.
   */
  struct WearLawPlugin
  {
    static constexpr const char *kind = "wear law", *section = "Wear",
                                *selector = "Wear law";
    std::string  name;
    std::string  documentation;
    ModelEntries entries;
    std::function<std::unique_ptr<WearLaw>(const Parameters::Wear &,
                                           const std::any &)>
      create;
  };

  /** The registered wear laws. */
  using WearLaws = Registry<WearLawPlugin>;

  /** The law of `Wear/Wear law` with its constants and the run-in. */
  std::unique_ptr<WearLaw>
  create_wear_law(const Parameters::Wear &parameters);

  /** The worn volume, depth and area of a depth field on the worn surface. */
  struct WearMeasures
  {
    /** sum_j depth_j A_j (mm^3). */
    double volume = 0;
    /** Largest depth (mm). */
    double max_depth = 0;
    /** Area of the nodes whose scaled depth exceeds the threshold, and of
     *  all nodes (mm^2). */
    double worn_area = 0, area = 0;

    /** The worn area in percent of the whole surface. */
    double
    worn_percent() const
    {
      return area > 0 ? 100. * worn_area / area : 0.;
    }
  };

  /**
   * The measures of the nodal @p depth (mm) on a surface with the nodal
   * areas @p nodal_area (mm^2): a node counts as worn where
   * @p depth_scale x depth exceeds @p threshold (mm), e.g. the depth of
   * one cycle scaled to the cycles of the test, or the accumulated depth
   * with scale 1.
   */
  WearMeasures
  measure_wear(const std::vector<double> &depth,
               const std::vector<double> &nodal_area,
               const double               threshold,
               const double               depth_scale = 1.);
} // namespace TKR::Wear

#endif
