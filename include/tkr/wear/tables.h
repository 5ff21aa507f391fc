// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_tables_h
#define tkr_wear_tables_h

#include <tkr/wear/cross_shear.h>

#include <string>
#include <utility>
#include <vector>

namespace TKR::Wear
{
  /**
   * A piecewise linear function of one variable through the points
   * (x_i, y_i), x strictly increasing, constant beyond the first and the
   * last point (a single point: a constant).
   */
  class PiecewiseLinear
  {
  public:
    PiecewiseLinear() = default;

    PiecewiseLinear(std::vector<double> x, std::vector<double> y);

    double
    value(const double x) const;

    /** The exact integral from @p a to @p b (a <= b). */
    double
    integral(const double a, const double b) const;

    bool
    empty() const
    {
      return xs.empty();
    }

    /** The points (x, y) that define the function. */
    std::vector<std::pair<double, double>>
    points() const;

  private:
    /** The integral from the first point to @p x (negative before it). */
    double
    primitive(const double x) const;

    std::vector<double> xs, ys;
  };

  /**
   * The run-in of `Wear/Run-in file` (doc/wear.md, "Run-in"): a CSV file
   * with the columns `cycles` and `factor` (cycles from 0, increasing;
   * factors >= 0), the factor on the wear rate, piecewise linear in the
   * cycle count and constant beyond the last row.
   */
  PiecewiseLinear
  read_run_in(const std::string &filename);

  /**
   * A wear law's coefficient as a function of the cross-shear ratio, and
   * optionally of the contact pressure (doc/wear.md, "Cross-shear
   * tables"): a CSV file with the columns `cross_shear` and the law's
   * value column, and possibly `pressure_MPa`. Without pressures, one
   * piecewise linear function of the cross-shear (rows in increasing
   * cross-shear); with pressures, the rows of each pressure together (in
   * increasing pressure, each block in increasing cross-shear), piecewise
   * linear in the cross-shear at each pressure and linear between
   * pressures; constant beyond the first and last row either way.
   */
  class CrossShearTable
  {
  public:
    CrossShearTable() = default;

    /**
     * Read @p filename's columns `cross_shear` (`cross_shear_abs_sin` for
     * the |sin| @p definition: the column says which definition the table
     * was fitted with, and a table of the other is refused), @p
     * value_column and (if @p with_pressure) `pressure_MPa`; ExcInputError
     * naming the file and line on bad input (negative values, a ratio
     * beyond the definition's largest).
     */
    CrossShearTable(const std::string         &filename,
                    const std::string         &value_column,
                    const bool                 with_pressure,
                    const CrossShearDefinition definition =
                      CrossShearDefinition::work_tensor);

    /** The value at cross-shear @p cs and pressure @p p (MPa). */
    double
    value(const double cs, const double p = 0) const;

    /** Whether the table depends on the pressure. */
    bool
    depends_on_pressure() const
    {
      return pressures.size() > 1;
    }

    /** The file it was read from. */
    const std::string &
    file() const
    {
      return filename;
    }

  private:
    std::string filename;
    /** The pressures (one 0 without a pressure column) and, per pressure,
     *  the function of the cross-shear. */
    std::vector<double>          pressures;
    std::vector<PiecewiseLinear> of_cross_shear;
  };
} // namespace TKR::Wear

#endif
