; "Keeping All Objects Near": three demonstrations eliminate the colour and the context from
; the rules r_1^1 .. r_3^1, leaving "no block is far", which holds for any number of blocks
; of any colour. Here: four blocks, two of colours never demonstrated.
(define (problem keep-all-near)
  (:domain vsl-sp)
  (:objects green orange purple blue - block)
  (:init
    (far green)
    (far purple)
    (far blue))
  (:goal (forall (?b - block) (not (far ?b)))))
