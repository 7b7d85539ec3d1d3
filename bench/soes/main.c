/* The SOES firmware of the size benchmark (bench/soes/size.sh): SOES's init, then its free-run
 * polling loop; the application moves 8 inputs and 8 outputs, and drives the outputs low when
 * SOES stops them (SAFEOP, as ecat's digital I/O does).
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#include "ecat_slv.h"
#include "utypes.h"
#include "board.h"

_Objects Obj;

void cb_get_inputs (void)
{
   Obj.BUTTON = board_inputs ();
}

void cb_set_outputs (void)
{
   board_outputs ((uint8_t) Obj.LED);
}

static void safe_outputs (void)
{
   Obj.LED = 0;
   board_outputs (0);
}

int main (void)
{
   static esc_cfg_t config = {
      .use_interrupt = 0,
      .watchdog_cnt = 150,
      .safeoutput_override = safe_outputs,
   };

   ecat_slv_init (&config);
   for (;;)
   {
      ecat_slv ();
   }
}
