; A goal Fast Downward's translator cannot take: three nested foralls over an (or ...) of three
; atoms. Its normal form (a disjunction of every choice of one atom per ground instance) grows
; past 20 GB without a memory limit; vslsp's default limits end it (issue 27).
(define (problem forall-blowup)
  (:domain vsl-sp)
  (:objects red green blue - block)
  (:init (far red))
  (:goal (forall (?a - block)
           (forall (?b - block)
             (forall (?c - block)
               (or (far ?a) (far ?b) (far ?c)))))))
