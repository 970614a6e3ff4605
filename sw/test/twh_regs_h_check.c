/* Compile-only check of the generated register header (make check-regs):
 * it must build as gnu99 with -Wall -Wextra -Werror -pedantic, for the host
 * and for arm-none-eabi. Offsets and field macros are checked against the
 * RDL by tb/test_regmap_py.py; the members below are the register map
 * version 2 ones the C driver uses (sw/src/twh.c), so a header without
 * them fails here already. */
#include <stdint.h>
#include "twh_regs.h"

uint32_t twh_regs_h_check(const volatile twh_regs_t *regs);

uint32_t twh_regs_h_check(const volatile twh_regs_t *regs)
{
    return ((regs->ID & TWH_REGS__ID__MAGIC_bm) >> TWH_REGS__ID__MAGIC_bp) ^ regs->IDLE_CHARGE ^
           regs->BUSY ^ regs->CH[31].CMD_PUSH ^
           (uint32_t)TWH_REGS__CHANNEL_T__CMD_PUSH__TAG_bm ^ (uint32_t)TWH_REGS__RES_POP__CHANNEL_bm;
}
