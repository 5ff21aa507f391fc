// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Private to source/contact: the sums of scaled stored columns that the
// condensed active-set solver's zone, Newton step and displacement make.

#ifndef tkr_source_contact_term_sum_h
#define tkr_source_contact_term_sum_h

namespace TKR::Contact
{
  /**
   * target[k] += v[0] g[0][k] + ... + v[n_terms - 1] g[n_terms - 1][k] for
   * k < n, 1 to 4 terms, the products added one after the other (the
   * same floating-point sums as one axpy per term, in one pass over
   * target instead of n_terms). Compiled for AVX2 as well (without FMA,
   * so that both versions give the same bits); the processor picks.
   */
  void
  add_terms(double *__restrict target,
            const double *const *g,
            const double        *v,
            const unsigned int   n_terms,
            const unsigned int   n);

  /**
   * Adds terms for add_terms() and applies them four at a time, in the
   * order they came.
   */
  class TermSum
  {
  public:
    TermSum(double *target, const unsigned int n)
      : target(target)
      , n(n)
    {}

    void
    add(const double value, const double *values)
    {
      v[n_terms] = value;
      g[n_terms] = values;
      if (++n_terms == 4)
        flush();
    }

    void
    flush()
    {
      if (n_terms > 0)
        add_terms(target, g, v, n_terms, n);
      n_terms = 0;
    }

    ~TermSum()
    {
      flush();
    }

  private:
    double *const      target;
    const unsigned int n;
    const double      *g[4]    = {};
    double             v[4]    = {};
    unsigned int       n_terms = 0;
  };
} // namespace TKR::Contact

#endif
