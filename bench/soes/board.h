/* The "board" of the SOES size benchmark (bench/soes/size.sh): a polled SPI master with its
 * chip-select line and 8 digital inputs and 8 outputs, on the STM32G474's SPI1 and GPIOA/GPIOB
 * registers. Shared unchanged by the SOES firmware and the baseline, so it cancels out of the share.
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#ifndef BENCH_SOES_BOARD_H
#define BENCH_SOES_BOARD_H

#include <stddef.h>
#include <stdint.h>

/** Asserts the ESC's chip select: a transaction starts. */
void esc_spi_select (void);
/** Releases the chip select: the transaction ends. */
void esc_spi_unselect (void);
/** Clocks `len` bytes: sends `tx` (0x00 for each byte when `tx` is NULL), stores what the ESC
 * shifted out meanwhile into `rx` (discarded when `rx` is NULL). */
void esc_spi_transfer (uint8_t * rx, const uint8_t * tx, uint16_t len);
/** The 8 digital inputs, bit n = input n. */
uint8_t board_inputs (void);
/** Drives the 8 digital outputs, bit n = output n. */
void board_outputs (uint8_t bits);

#endif
