/* Compile-only check of the generated register header (make check-regs):
 * it must build as gnu99 with -Wall -Wextra -Werror -pedantic, for the host
 * and for arm-none-eabi. Offsets and field macros are checked against the
 * RDL by tb/test_regmap_py.py. */
#include <stdint.h>
#include "twh_regs.h"

uint32_t twh_regs_h_check(const volatile twh_regs_t *regs);

uint32_t twh_regs_h_check(const volatile twh_regs_t *regs)
{
    return (regs->ID & TWH_REGS__ID__MAGIC_bm) >> TWH_REGS__ID__MAGIC_bp;
}
