/* The application's objects for SOES's sample object list (applications/tiesc_am335x's
 * am335xice_objectlist.c: 0x6000 BUTTON and 0x7000 LED, an UNSIGNED32 each) and, with
 * SOES_SYNC_PARAMS, the storage of 0x1C32 as SOES's applications/rtl_xmc4_dynpdo declares it,
 * twice (0x1C33 is its copy; see size.sh).
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#ifndef __UTYPES_H__
#define __UTYPES_H__

#include "cc.h"

#ifdef SOES_SYNC_PARAMS
typedef struct
{
   uint16_t Sync_mode;
   uint32_t CycleTime;
   uint32_t ShiftTime;
   uint16_t Sync_modes_supported;
   uint32_t Minimum_Cycle_Time;
   uint32_t Calc_and_Copy_Time;
   uint32_t Minimum_Delay_Time;
   uint16_t GetCycleTime;
   uint32_t DelayTime;
   uint32_t Sync0CycleTime;
   uint16_t SMEventMissedCnt;
   uint16_t CycleTimeTooSmallCnt;
   uint16_t Shift_too_short_counter;
   uint16_t RxPDOToggleFailed;
   uint32_t Minimum_Cycle_Distance;
   uint32_t Maximum_Cycle_Distance;
   uint32_t Minimum_SM_Sync_Distance;
   uint32_t Maximum_SM_Sync_Distance;
   uint8_t SyncError;
} SyncParams;
#endif

typedef struct
{
   /* Inputs: 8 digital inputs in the low byte */
   uint32_t BUTTON;
   /* Outputs: 8 digital outputs in the low byte */
   uint32_t LED;
#ifdef SOES_SYNC_PARAMS
   SyncParams SyncMgrParam;   /* 0x1C32 */
   SyncParams SyncMgrParamIn; /* 0x1C33 */
#endif
} _Objects;

extern _Objects Obj;

#endif /* __UTYPES_H__ */
