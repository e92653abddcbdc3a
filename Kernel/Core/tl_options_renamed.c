/* Refusal of renamed options (see tl_options_renamed.h). */
#include "tl_options_renamed.h"

TlStatus tl_options_refuse_renamed(TlOptions *o, const TlRenamedOption *table, int n)
{
  if (!o || (n > 0 && !table)) TL_ERROR(TL_ERR_ARG, "tl_options_refuse_renamed: null options or table");
  for (int i = 0; i < n; ++i) {
    if (!table[i].old_name || !table[i].new_name)
      TL_ERROR(TL_ERR_ARG, "tl_options_refuse_renamed: entry %d has no old or new name", i);
    if (!tl_options_has(o, table[i].old_name)) continue;
    if (table[i].note && table[i].note[0])
      TL_ERROR(TL_ERR_ARG, "option %s was renamed %s (%s): give %s instead", table[i].old_name, table[i].new_name,
               table[i].note, table[i].new_name);
    TL_ERROR(TL_ERR_ARG, "option %s was renamed %s (one name for one thing in every driver): give %s instead",
             table[i].old_name, table[i].new_name, table[i].new_name);
  }
  return TL_OK;
}
