/* crt0.S - start-up and interrupt entry of the hfi_soc firmware (PicoRV32, RV32IM).
 *
 * 0x000 reset: set sp and gp, clear .bss, call main().
 * 0x010 interrupt (PicoRV32 PROGADDR_IRQ, ENABLE_IRQ_QREGS): q0 holds the return address, q1 the
 *       bit mask of the pending interrupts. The entry saves the caller-saved registers on the
 *       current stack, calls irq_handler(q1), restores them and returns with retirq. Interrupts
 *       are masked by the core while the handler runs.
 * PicoRV32's custom instructions (getq, retirq, maskirq) are emitted as .insn (R-type, opcode 0x0B)
 * with the encodings of its documentation. */

#define GETQ(rd, qs)   .insn r 0x0B, 4, 0, rd, x##qs, x0
#define RETIRQ         .insn r 0x0B, 0, 2, x0, x0, x0
#define MASKIRQ(rd, rs) .insn r 0x0B, 6, 3, rd, rs, x0

    .section .vectors, "ax"
    .globl _start
_start:
    j reset
    .balign 16
irq_entry:
    addi sp, sp, -64
    sw ra, 0(sp)
    sw t0, 4(sp)
    sw t1, 8(sp)
    sw t2, 12(sp)
    sw a0, 16(sp)
    sw a1, 20(sp)
    sw a2, 24(sp)
    sw a3, 28(sp)
    sw a4, 32(sp)
    sw a5, 36(sp)
    sw a6, 40(sp)
    sw a7, 44(sp)
    sw t3, 48(sp)
    sw t4, 52(sp)
    sw t5, 56(sp)
    sw t6, 60(sp)
    GETQ(a0, 1)
    call irq_handler
    lw ra, 0(sp)
    lw t0, 4(sp)
    lw t1, 8(sp)
    lw t2, 12(sp)
    lw a0, 16(sp)
    lw a1, 20(sp)
    lw a2, 24(sp)
    lw a3, 28(sp)
    lw a4, 32(sp)
    lw a5, 36(sp)
    lw a6, 40(sp)
    lw a7, 44(sp)
    lw t3, 48(sp)
    lw t4, 52(sp)
    lw t5, 56(sp)
    lw t6, 60(sp)
    addi sp, sp, 64
    RETIRQ

reset:
    la sp, _stack_top
    li t0, -1
    MASKIRQ(x0, t0)             /* all interrupts masked until main() unmasks them */
    la t0, _bss_start
    la t1, _bss_end
1:  bgeu t0, t1, 2f
    sw zero, 0(t0)
    addi t0, t0, 4
    j 1b
2:  call main
3:  j 3b

    .text
    .globl irq_mask
/* uint32_t irq_mask(uint32_t mask): set the interrupt mask (1 = masked), return the old one. */
irq_mask:
    MASKIRQ(a0, a0)
    ret
