/* Cortex-M4 startup of the SOES size benchmark, shared by the SOES firmware and the baseline: the
 * vector table's first entries, .data copied from flash by memcpy, .bss zeroed, then main. So the
 * baseline carries libc's memcpy, as examples/stm32's carries compiler_builtins' memcpy; .bss is
 * zeroed through a volatile pointer, which gcc cannot turn into a memset call: the memset SOES
 * needs is charged to SOES (ecat's firmware has none).
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#include <stdint.h>
#include <string.h>

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern int main (void);

void Reset_Handler (void)
{
   memcpy (&_sdata, &_sidata, (size_t) ((char *) &_edata - (char *) &_sdata));
   for (volatile uint32_t * to = &_sbss; to < &_ebss;)
   {
      *to++ = 0;
   }
   main ();
   for (;;)
   {
   }
}

static void Default_Handler (void)
{
   for (;;)
   {
   }
}

__attribute__ ((section (".isr_vector"), used))
static void (*const vectors[]) (void) = {
   (void (*) (void)) &_estack,
   Reset_Handler,
   Default_Handler, /* NMI */
   Default_Handler, /* HardFault */
};
