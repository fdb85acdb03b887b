/* units.h: the unit conversions and numeric constants the tools share, in one place (internal
 * units: mm, MPa, N, deg, D; keratome-scene(5)). */
#ifndef KT_UNITS_H
#define KT_UNITS_H

/* MPa per mmHg: the conventional millimetre of mercury, 133.322387415 Pa (ISO 80000-4). */
#define KT_MMHG_MPA 133.322387415e-6

/* Keratometric power times radius, D mm: 1000 (n - 1) with the keratometric index n = 1.3375,
 * K = 337.5 / R (curvature(1); keratome-patient(5)). */
#define KT_N_KERATO 337.5

/* The two-sided 90% quantile of the standard normal distribution (the bands' +- 1.645 sd). */
#define KT_Z90 1.6448536269514722

#endif
