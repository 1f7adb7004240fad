#include "epi/antialias.h"

#include "epi/geometry.h"
#include "epi/tables.h"

namespace epi {

void antialias_pixel(const EpiRows& epi, int x, int y, const float* const rows[3], float out[3]) {
  const float* own = rows[1] + 3 * x;
  const int type = epi.type_at(x, y);
  out[0] = own[0], out[1] = own[1], out[2] = own[2];
  if (!type_is_simple(type)) return;
  const EpiTables& t = epi_tables();
  const int code = edge_code(epi.edge_at(x, y));
  const bool primary_is_b = (type - 2) & 1;
  const int k = t.neighbour_for_secondary(code, !primary_is_b);
  const int nx = x + kNeighbourDx[k], dy = kNeighbourDy[k];
  if (nx < 0 || nx >= epi.width || !rows[1 + dy]) return;
  const float* secondary = rows[1 + dy] + 3 * nx;
  const float area_a = t.area_of_a(code);
  const float a = primary_is_b ? 1.0f - area_a : area_a;
  for (int c = 0; c < 3; ++c) out[c] = a * own[c] + (1.0f - a) * secondary[c];
}

}  // namespace epi
