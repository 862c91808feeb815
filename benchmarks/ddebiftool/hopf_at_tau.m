function [pt,ok]=hopf_at_tau(funcs,ip,hbr,near,tau)
%% Hopf point at exactly this tau, corrected in (k, c) from the point `near`
% of a Hopf curve (hbr supplies the method; the pinning z(0)=0 is active)
pt=near; pt.parameter(ip.tau)=tau;
mth=hbr.method.point; mth.extra_condition=1;
[pt,ok]=p_correc(funcs,pt,[ip.k,ip.c],[],mth);
end
