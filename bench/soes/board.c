/* The board of the SOES size benchmark (board.h): register-level polled SPI and GPIO, as small as a
 * real driver gets, so neither build is charged for a HAL.
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#include "board.h"

#define REG(addr) (*(volatile uint32_t *) (addr))
#define REG8(addr) (*(volatile uint8_t *) (addr))

#define SPI1_SR     REG (0x40013008u)
#define SPI1_DR     REG8 (0x4001300Cu)
#define SPI_SR_RXNE (1u << 0)
#define SPI_SR_TXE  (1u << 1)

#define GPIOA_BSRR  REG (0x48000018u)
#define GPIOB_IDR   REG (0x48000410u)
#define GPIOB_ODR   REG (0x48000414u)
#define CS_PIN      4u

void esc_spi_select (void)
{
   GPIOA_BSRR = 1u << (CS_PIN + 16u);
}

void esc_spi_unselect (void)
{
   GPIOA_BSRR = 1u << CS_PIN;
}

void esc_spi_transfer (uint8_t * rx, const uint8_t * tx, uint16_t len)
{
   for (uint16_t i = 0; i < len; i++)
   {
      while ((SPI1_SR & SPI_SR_TXE) == 0)
      {
      }
      SPI1_DR = (tx != NULL) ? tx[i] : 0x00;
      while ((SPI1_SR & SPI_SR_RXNE) == 0)
      {
      }
      uint8_t byte = SPI1_DR;
      if (rx != NULL)
      {
         rx[i] = byte;
      }
   }
}

uint8_t board_inputs (void)
{
   return (uint8_t) GPIOB_IDR;
}

void board_outputs (uint8_t bits)
{
   GPIOB_ODR = (GPIOB_ODR & ~0xFF00u) | ((uint32_t) bits << 8);
}
