#ifndef SPLAM_IO_NO_RETURN_PILE_H_
#define SPLAM_IO_NO_RETURN_PILE_H_

#include <optional>

#include "io/carmen.h"

// Lasers that write their no-returns as a range without saying so. A SICK logged through some
// drivers writes "nothing hit" as a value near its maximum (MIT Killian Court: 51.05-51.12 m,
// 1.3 % of the readings, below the FLASER convention's 81.8 m); taken as hits, they are a wall
// of points on an arc around the robot wherever it looks down a long corridor or across a hall.
// Such readings pile up in a narrow band at the very top of the log's range distribution, where
// real returns thin out.
namespace splam::io {

struct NoReturnPileOptions {
  // The band at the top of the distribution: readings within band_m of the largest, m.
  double band_m = 0.5;
  // A pile holds at least min_share of all the log's readings that are hits...
  double min_share = 0.001;
  // ...and is at least min_density_ratio times as dense (readings per metre) as the
  // below_m below the band.
  double below_m = 5.0;
  double min_density_ratio = 20.0;
  // ...and lies at least min_times_median times the hits' median range: a no-return value is
  // far beyond the scene a laser mostly sees (a robot parked in front of a wall piles all its
  // readings at one range too).
  double min_times_median = 3.0;
};

struct NoReturnPile {
  double from_m = 0.0;  // the band's smallest reading: readings at or above are no-returns
  double to_m = 0.0;    // the largest reading
  long readings = 0;    // in the band
  double share = 0.0;   // of the log's hits
};

// The pile at the top of the hits' range distribution, if the log's lasers have one.
std::optional<NoReturnPile> FindNoReturnPile(const CarmenLog& log,
                                             const NoReturnPileOptions& options = {});

// Marks every laser reading at or above from_m as a no-return, and lowers each scan's maximum
// range to from_m where it was above.
void MarkNoReturns(double from_m, CarmenLog* log);

}  // namespace splam::io

#endif  // SPLAM_IO_NO_RETURN_PILE_H_
