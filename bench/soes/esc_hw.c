/* SOES's ESC hardware layer (ESC_read, ESC_write, ESC_reset, ESC_init; soes/esc.h) for an ET1100,
 * ET1200 or AX58100 on SPI, speaking the Beckhoff ESC SPI protocol (ESC datasheet section II, "SPI
 * Slave Interface"), written for the size benchmark after SOES's own SPI layers
 * (soes/hal/rt-kernel-twrk60, soes/hal/rt-kernel-lan9252) and ecat-embassy/src/spi/beckhoff.rs:
 *
 *   2-byte addressing:  A[12:5]  A[4:0] CMD0                          [0xFF wait]  D0 D1 …
 *   3-byte addressing:  A[12:5]  A[4:0] 110b  A[15:13] CMD1 00b       [0xFF wait]  D0 D1 …
 *   MISO meanwhile:     0x0220   0x0221       0x0222                  (the AL event)
 *
 * Reads send the wait state byte (works at any SPI clock the ESC supports) and 0x00 with every
 * data byte but the last, which carries the read termination 0xFF. Every access is one
 * transaction, and the AL event the ESC shifts out during the address phase is kept in
 * ESCvar.ALevent, as SOES expects of an ET1x00 layer.
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#include "esc.h"
#include "board.h"

#define ESC_CMD_READ_WAIT_STATE 0x03u
#define ESC_CMD_WRITE           0x04u
#define ESC_CMD_EXTENDED        0x06u
#define ESC_WAIT_STATE          0xFFu
#define ESC_READ_TERMINATION    0xFFu

/* Selects the ESC and sends the address phase of `command` at `address` (plus the wait state byte
 * of a read), keeping the AL event shifted out meanwhile. */
static void esc_address (uint16_t address, uint8_t command)
{
   uint8_t phase[4];
   uint8_t event[4] = { 0 };
   uint16_t len;

   phase[0] = (uint8_t) (address >> 5);
   if (address < 0x2000u)
   {
      phase[1] = (uint8_t) ((address & 0x1Fu) << 3) | command;
      len = 2;
   }
   else
   {
      phase[1] = (uint8_t) ((address & 0x1Fu) << 3) | ESC_CMD_EXTENDED;
      phase[2] = (uint8_t) (((address >> 8) & 0xE0u) | (command << 2));
      len = 3;
   }
   if (command == ESC_CMD_READ_WAIT_STATE)
   {
      phase[len++] = ESC_WAIT_STATE;
   }

   esc_spi_select ();
   esc_spi_transfer (event, phase, len);
   ESCvar.ALevent = etohl ((uint32_t) event[0] | ((uint32_t) event[1] << 8) |
                           ((address < 0x2000u) ? 0u : ((uint32_t) event[2] << 16)));
}

/** ESC read function used by the slave stack.
 *
 * @param[in]   address     = address of ESC register to read
 * @param[out]  buf         = pointer to buffer to read in
 * @param[in]   len         = number of bytes to read
 */
void ESC_read (uint16_t address, void * buf, uint16_t len)
{
   static const uint8_t termination = ESC_READ_TERMINATION;
   uint8_t * bytes = buf;

   esc_address (address, ESC_CMD_READ_WAIT_STATE);
   if (len > 0)
   {
      esc_spi_transfer (bytes, NULL, len - 1);
      esc_spi_transfer (bytes + len - 1, &termination, 1);
   }
   esc_spi_unselect ();
}

/** ESC write function used by the slave stack.
 *
 * @param[in]   address     = address of ESC register to write
 * @param[in]   buf         = pointer to buffer to write from
 * @param[in]   len         = number of bytes to write
 */
void ESC_write (uint16_t address, void * buf, uint16_t len)
{
   esc_address (address, ESC_CMD_WRITE);
   esc_spi_transfer (NULL, buf, len);
   esc_spi_unselect ();
}

/* The ESC needs no reset sequence over SPI; the board holds no reset line. */
void ESC_reset (void)
{
}

/* The board configured the SPI peripheral (mode 3) before the stack starts. */
void ESC_init (const esc_cfg_t * config)
{
   (void) config;
}
