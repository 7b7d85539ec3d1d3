/* The size baseline of the SOES benchmark (bench/soes/size.sh), as examples/stm32's `baseline` is
 * ecat's: the same startup, board and SPI transfer as main.c without SOES, in a trivial loop (one
 * SPI transaction, the outputs from it, the inputs into the next), so nothing of the board is
 * dropped. SOES's share = the SOES firmware less this.
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#include "board.h"

int main (void)
{
   uint8_t frame[4] = { 0 };

   for (;;)
   {
      esc_spi_select ();
      esc_spi_transfer (frame, frame, sizeof (frame));
      esc_spi_unselect ();
      board_outputs (frame[3]);
      frame[0] = board_inputs ();
   }
}
