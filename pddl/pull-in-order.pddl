; "Pull All Objects in a Given Order": one demonstration pulls orange, then green, then
; yellow. The paper writes the order as "somewhere-after", which PDDL 3.0 does not have;
; (sometime-before p q) says p may only hold after q has held.
(define (problem pull-in-order)
  (:domain vsl-sp)
  (:objects orange green yellow - block)
  (:init
    (far orange)
    (far green)
    (far yellow))
  (:goal (and
    (not (far orange))
    (not (far green))
    (not (far yellow))))
  (:constraints (and
    (sometime-before (not (far green)) (not (far orange)))
    (sometime-before (not (far yellow)) (not (far green))))))
